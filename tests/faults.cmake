# Failures on one rank end the job, never hang it (docs/architecture.md,
# "Errors"): faults injected on one rank of a 2-rank `sphdem run`
# (SPHDEM_INJECT_FAULT) abort it at once with the class's exit status; a
# collective failure exits cleanly with its status and the last state.
# The timeout is far below a hang's: each scenario takes a few seconds.
foreach(_scenario simulation runtime snapshot_write checkpoint_write restart_read full_disk
                  no_progress input dem blowup bad_input one_rank)
  add_test(NAME faults_${_scenario}
           COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_faults.py ${_scenario}
                   $<TARGET_FILE:sphdem> ${PROJECT_SOURCE_DIR}
                   ${CMAKE_CURRENT_BINARY_DIR}/faults_work/${_scenario}
                   ${MPIEXEC_EXECUTABLE} ${SPHDEM_MPIEXEC_FLAGS})
  set_tests_properties(faults_${_scenario} PROPERTIES LABELS "cli;mpi;faults" TIMEOUT 60
                                                      PROCESSORS 2)
endforeach()
