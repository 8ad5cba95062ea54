# Checkpoint and restart (issue 6, docs/checkpoint.md).
# In process: restarts are bitwise at 1, 2 and 3 ranks (checkpoint written on
# P - 1 ranks, restarted on P - 1, P and 1), foreign checkpoints refused.
# 4 s on a quiet machine; 3 oversubscribed ranks on a loaded one took over 120 s.
sphdem_test(test_checkpoint SOURCES test_checkpoint.cpp RANKS 1 2 3 LABELS "unit;checkpoint"
            TIMEOUT 300)

# End to end through `sphdem run` (tests/check_checkpoint.py): a stop signal
# (SIGTERM to one rank, SIGUSR1 to mpiexec), SIGKILL of one rank, a crash
# between the data write and the rename, and refused checkpoints (truncated,
# corrupt, another case, another format, an output directory in use), and the
# fibers-only runs in 2D (dem) and 3D (dem3d) restarted on other rank counts.
foreach(_scenario sigterm sigusr1 sigterm_mpiexec sigkill abort_in_write refused dem dem3d)
  add_test(NAME checkpoint_${_scenario}
           COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_checkpoint.py ${_scenario}
                   $<TARGET_FILE:sphdem> ${PROJECT_SOURCE_DIR}
                   ${CMAKE_CURRENT_BINARY_DIR}/checkpoint_work/${_scenario}
                   ${MPIEXEC_EXECUTABLE} ${SPHDEM_MPIEXEC_FLAGS})
  set_tests_properties(checkpoint_${_scenario} PROPERTIES LABELS "cli;checkpoint" TIMEOUT 180
                                                          PROCESSORS 2)
endforeach()
