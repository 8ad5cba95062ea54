# The analysis tools (tools/*.py, docs/tools.md) on small synthetic runs
# written by h5py in sphdem's snapshot layout, with known answers: velocity
# profile fit, orientation tensor, fiber counts, bond stresses, the PNGs,
# --help and the error messages. Python only: no sphdem run needed.
# (tests/CMakeLists.txt includes every tests/*.cmake, this file too.)
add_test(NAME tools_analysis
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_tools.py)
set_tests_properties(tools_analysis PROPERTIES LABELS "tools" TIMEOUT 400
                                               ENVIRONMENT "MPLBACKEND=Agg")
