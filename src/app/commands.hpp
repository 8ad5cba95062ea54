#pragma once
namespace sphdem::app {
// Parses the command line and runs the chosen sub-command; returns the exit
// status. Throws InputError / SimulationError (handled by main).
int dispatch(int argc, char** argv);
}  // namespace sphdem::app
