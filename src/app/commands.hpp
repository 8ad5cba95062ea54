#pragma once
namespace sphdem::app {
// Parses the command line and runs the chosen sub-command; returns the exit
// status. Throws the collective errors main handles (InputError,
// CollectiveSimulationError); anything else is a one-rank failure that
// aborts the job (fault_handler.hpp).
int dispatch(int argc, char** argv);
}  // namespace sphdem::app
