# tools/paper_seeds.sh and tools/paper_seeds.py (issue 12 part 7): --help, bad
# options, the dry run's order of runs, and the analysis on hand-made snapshots
# against hand values (no sphdem runs). (tests/CMakeLists.txt includes every
# tests/*.cmake.)
add_test(NAME paper_seeds_tools
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_paper_seeds.py
                 ${PROJECT_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/paper_seeds_work)
set_tests_properties(paper_seeds_tools PROPERTIES LABELS "tools" TIMEOUT 120)
