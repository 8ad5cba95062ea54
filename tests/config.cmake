sphdem_test(test_config SOURCES test_config.cpp RANKS 1 LABELS unit)
sphdem_test(test_schema SOURCES test_schema.cpp RANKS 1 LABELS unit)

# docs/case-file.md is generated from the key schema: fail when it is stale.
add_test(NAME case_file_doc_current
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_case_file_doc.py
                 $<TARGET_FILE:sphdem> ${PROJECT_SOURCE_DIR}/docs/case-file.md)
set_tests_properties(case_file_doc_current PROPERTIES LABELS "unit;docs" TIMEOUT 60)

# Every repository path, tool, case and case key the docs name exists, and no
# file cites a document outside the repository.
add_test(NAME doc_paths_exist
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_doc_paths.py ${PROJECT_SOURCE_DIR}
                 --sphdem $<TARGET_FILE:sphdem>)
set_tests_properties(doc_paths_exist PROPERTIES LABELS "unit;docs" TIMEOUT 60)
