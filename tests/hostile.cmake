# Hostile input (issue 15, defects 3, 6, 7, 8): case files refused at
# file:line:key (test_hostile_input), and through the command line
# (tests/check_hostile_input.py): the size guard of check and run, bad
# files, edited checkpoint attributes with nothing deleted.
sphdem_test(test_hostile_input SOURCES test_hostile_input.cpp RANKS 1 LABELS "unit;hostile")
foreach(_scenario size files restart)
  add_test(NAME hostile_${_scenario}
           COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_hostile_input.py ${_scenario}
                   $<TARGET_FILE:sphdem> ${PROJECT_SOURCE_DIR}
                   ${CMAKE_CURRENT_BINARY_DIR}/hostile_work/${_scenario}
                   ${MPIEXEC_EXECUTABLE} ${SPHDEM_MPIEXEC_FLAGS})
  set_tests_properties(hostile_${_scenario} PROPERTIES LABELS "cli;hostile" TIMEOUT 300
                                                       PROCESSORS 2)
endforeach()
