# `sphdem check --ranks P --memory-per-rank M` (issue 14 part 4,
# docs/scaling.md, "Memory per rank"): exit codes and messages, the 1e-6 m
# plate refused from its geometry alone.
add_test(NAME memory_estimate_cli
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_memory_estimate.py
                 $<TARGET_FILE:sphdem> ${PROJECT_SOURCE_DIR}
                 ${CMAKE_CURRENT_BINARY_DIR}/memory_estimate_work)
set_tests_properties(memory_estimate_cli PROPERTIES LABELS "cli" TIMEOUT 120)
