#pragma once
// SIGTERM and SIGUSR1 (what SLURM and PBS send before a job's time limit,
// docs/checkpoint.md) ask the run to stop: the handler only sets a flag,
// which the step loop polls after each step, and the run then writes a
// checkpoint and exits 0.
namespace sphdem::app {

void install_stop_signals();
bool stop_requested();
int stop_signal();  // the signal that asked, 0 if none

}  // namespace sphdem::app
