# Fuzz test of the case loader (issue 15, tests/fuzz_case_files.py): a few
# hundred mutated copies of inputs/*.yaml through `sphdem check`, two at a
# time; each must exit 0, or 2 with a file:line message, never a signal, a
# hang or exit 1/3. Instrumented code (the sanitize preset) runs several
# times slower: fewer cases there; each case's timeout stretches with
# SPHDEM_TEST_TIMEOUT_SCALE (tests/CMakeLists.txt).
set(_fuzz_args --cases 300 --timeout 60)
if(SPHDEM_SANITIZE)
  set(_fuzz_args --cases 120 --timeout 60)
endif()
add_test(NAME fuzz_case_files
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/fuzz_case_files.py
                 $<TARGET_FILE:sphdem> ${PROJECT_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/fuzz_work
                 --jobs 2 ${_fuzz_args})
set_tests_properties(fuzz_case_files PROPERTIES LABELS "fuzz;cli" TIMEOUT 600 PROCESSORS 2)
