find_program(SPHDEM_CLANG_FORMAT clang-format)
if(SPHDEM_CLANG_FORMAT)
  add_test(NAME format_check COMMAND sh ${CMAKE_CURRENT_SOURCE_DIR}/check_format.sh
                                     ${PROJECT_SOURCE_DIR} ${SPHDEM_CLANG_FORMAT})
  set_tests_properties(format_check PROPERTIES LABELS "style" TIMEOUT 120)
else()
  message(STATUS "clang-format not found: the format_check test is not added")
endif()
