add_test(NAME cli_end_to_end
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_cli.py $<TARGET_FILE:sphdem>
                 ${PROJECT_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/cli_work)
set_tests_properties(cli_end_to_end PROPERTIES LABELS "cli" TIMEOUT 300)
set_tests_properties(cli_end_to_end PROPERTIES FIXTURES_SETUP cli_output)

# The output of a real run (cli_end_to_end's `run --steps 50`), opened by
# h5py and by ParaView's XDMF readers: 400 resin and 120 wall particles.
add_test(NAME run_output_h5py
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_snapshot.py
                 ${CMAKE_CURRENT_BINARY_DIR}/cli_work/run_out --case poiseuille --snapshots 3
                 --expect fluid=400 --expect wall=120)
set_tests_properties(run_output_h5py PROPERTIES FIXTURES_REQUIRED cli_output TIMEOUT 120
                                                LABELS "io;cli")
find_program(SPHDEM_PVPYTHON pvpython)
if(SPHDEM_PVPYTHON)
  add_test(NAME run_output_paraview
           COMMAND ${SPHDEM_PVPYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_paraview.py
                   ${CMAKE_CURRENT_BINARY_DIR}/cli_work/run_out/poiseuille.xdmf 400 120
                   velocity,density,pressure --times 3)
  set_tests_properties(run_output_paraview PROPERTIES FIXTURES_REQUIRED cli_output TIMEOUT 300
                                                      LABELS "io;paraview;cli")
endif()
