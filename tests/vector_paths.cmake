# The vector paths of the CPUs this build is not for: a -march=native build
# compiles one path of each `#if defined(__AVX512F__) / __AVX2__ / #else`
# block, so a warning in another (which -Werror turns into a failed build on
# that CPU) passes here. check_vector_paths.py compiles the sources that hold
# such paths again, syntax only, for x86-64, x86-64-v3 and x86-64-v4
# (docs/architecture.md "Vector paths").
add_test(NAME vector_paths_compile
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_vector_paths.py
                 ${PROJECT_SOURCE_DIR} ${PROJECT_BINARY_DIR})
set_tests_properties(vector_paths_compile PROPERTIES LABELS "style" TIMEOUT 900)
