# Bond stress peaks and broken fibers (issue 12 part 6, docs/dem.md "Bond
# stress peaks", "Broken fibers"): the bookkeeping and the fiber split by
# hand, then a fibers-only run whose bonds break, end to end
# (tests/check_breakage.py): 1, 2 and 3 ranks bitwise, a restart through the
# breaks on 1 and on 3 ranks bitwise, and tools/fiber_lengths.py on its output.
sphdem_test(test_breakage SOURCES test_breakage.cpp RANKS 1 LABELS "unit;dem")
add_test(NAME breakage_run
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_breakage.py
                 $<TARGET_FILE:sphdem> ${PROJECT_SOURCE_DIR}
                 ${CMAKE_CURRENT_BINARY_DIR}/breakage_work ${MPIEXEC_EXECUTABLE}
                 ${SPHDEM_MPIEXEC_FLAGS})
set_tests_properties(breakage_run PROPERTIES LABELS "dem;cli;checkpoint;tools" TIMEOUT 300
                                             PROCESSORS 2 ENVIRONMENT "MPLBACKEND=Agg")
