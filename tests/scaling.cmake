# `sphdem scaling` (docs/scaling.md, "Scaling studies of any case"): a
# two-point strong and weak study of a small coupled case, the CSV, the
# plot, and bad input. Runs sphdem on 1 and 2 ranks itself.
string(JOIN " " _scaling_mpiexec ${MPIEXEC_EXECUTABLE} ${SPHDEM_MPIEXEC_FLAGS})
add_test(NAME scaling_study
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_scaling.py $<TARGET_FILE:sphdem>
                 ${PROJECT_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/scaling_work "${_scaling_mpiexec}")
set_tests_properties(scaling_study PROPERTIES LABELS "cli;tools" TIMEOUT 300 PROCESSORS 2
                                              ENVIRONMENT "MPLBACKEND=Agg")
