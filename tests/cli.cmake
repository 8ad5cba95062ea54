add_test(NAME cli_end_to_end
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_cli.py $<TARGET_FILE:sphdem>
                 ${PROJECT_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/cli_work)
set_tests_properties(cli_end_to_end PROPERTIES LABELS "cli" TIMEOUT 300)
set_tests_properties(cli_end_to_end PROPERTIES FIXTURES_SETUP cli_output)

# The output of a real run (cli_end_to_end's `run --steps 50`), opened by
# h5py and by ParaView's XDMF readers: 400 resin and 80 wall particles
# (2 of the case's 3 layers lie within the support 2h: wall_band, geometry.hpp).
add_test(NAME run_output_h5py
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_snapshot.py
                 ${CMAKE_CURRENT_BINARY_DIR}/cli_work/run_out --case poiseuille --snapshots 3
                 --expect fluid=400 --expect wall=80)
set_tests_properties(run_output_h5py PROPERTIES FIXTURES_REQUIRED cli_output TIMEOUT 120
                                                LABELS "io;cli")
find_program(SPHDEM_PVPYTHON pvpython)
if(SPHDEM_PVPYTHON)
  add_test(NAME run_output_paraview
           COMMAND ${SPHDEM_PVPYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_paraview.py
                   ${CMAKE_CURRENT_BINARY_DIR}/cli_work/run_out/poiseuille.xdmf 400 80
                   velocity,density,pressure --times 3)
  set_tests_properties(run_output_paraview PROPERTIES FIXTURES_REQUIRED cli_output TIMEOUT 300
                                                      LABELS "io;paraview;cli")
endif()

# The tools answer --help and draw the real run's output.
add_test(NAME tools_help
         COMMAND sh -c "${SPHDEM_PYTHON} ${PROJECT_SOURCE_DIR}/tools/plot_snapshot.py --help && ${SPHDEM_PYTHON} ${PROJECT_SOURCE_DIR}/tools/plate_timeline.py --help && ${SPHDEM_PYTHON} ${PROJECT_SOURCE_DIR}/tools/melt_maps.py --help")
set_tests_properties(tools_help PROPERTIES LABELS "tools" TIMEOUT 60)
add_test(NAME tools_plot_run_output
         COMMAND ${SPHDEM_PYTHON} ${PROJECT_SOURCE_DIR}/tools/plot_snapshot.py
                 ${CMAKE_CURRENT_BINARY_DIR}/cli_work/run_out --field pressure
                 -o ${CMAKE_CURRENT_BINARY_DIR}/cli_work/run_out_pressure.png)
set_tests_properties(tools_plot_run_output PROPERTIES FIXTURES_REQUIRED cli_output LABELS "tools"
                                                      TIMEOUT 120)
