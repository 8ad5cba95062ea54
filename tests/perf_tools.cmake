# tools/bench_vs_lammps.sh (issue 19): --help, bad options, the dry run of the
# peer build, and the alternating rounds with stand-ins for both codes (no
# timings). (tests/CMakeLists.txt includes every tests/*.cmake.)
add_test(NAME bench_vs_lammps_script
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_bench_vs_lammps.py
                 ${PROJECT_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/bench_vs_lammps_work)
set_tests_properties(bench_vs_lammps_script PROPERTIES LABELS "tools" TIMEOUT 120)
