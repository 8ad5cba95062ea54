#pragma once
// One rank's failure ends the whole job (docs/architecture.md, "Errors").
// main catches only the collective errors (InputError,
// CollectiveSimulationError); any other exception finds no handler, and
// std::terminate runs the handler installed here: it prints
//   sphdem: rank R, step S: <cause>
// and calls MPI_Abort with the exception's exit status (errors.hpp), so
// mpirun stops every rank at once instead of leaving them waiting in a
// collective for the failed one.
namespace sphdem::app {

void install_fault_handler();

}  // namespace sphdem::app
