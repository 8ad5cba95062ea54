# The analysis tools (tools/*.py, docs/tools.md) on small synthetic runs
# written by h5py in sphdem's snapshot layout, with known answers: velocity
# profile fit, orientation tensor, fiber counts, bond stresses, the PNGs,
# --help and the error messages. Python only: no sphdem run needed.
# (tests/CMakeLists.txt includes every tests/*.cmake, this file too.)
add_test(NAME tools_analysis
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_tools.py)
set_tests_properties(tools_analysis PROPERTIES LABELS "tools" TIMEOUT 400
                                               ENVIRONMENT "MPLBACKEND=Agg")

# Every program and Python module the tests run comes with the packages that
# scripts/install-deps.sh installs by default (a fresh clone's CI once failed
# because hyperfine came only with --peer). The second test drops hyperfine
# from the list and expects the check to name it.
add_test(NAME install_deps_cover_the_tests
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_install_deps.py
                 ${PROJECT_SOURCE_DIR})
add_test(NAME install_deps_check_names_a_missing_package
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_install_deps.py
                 ${PROJECT_SOURCE_DIR} --drop hyperfine)
set_tests_properties(install_deps_cover_the_tests install_deps_check_names_a_missing_package
                     PROPERTIES LABELS "tools;unit" TIMEOUT 60)
set_tests_properties(install_deps_check_names_a_missing_package PROPERTIES
  PASS_REGULAR_EXPRESSION "check_bench_vs_lammps.py: runs 'hyperfine', package 'hyperfine' is not")
