# ParaView and the run tools on a real output (docs/tools.md, "ParaView",
# "render.py", "report.py"): a tiny coupled run (inputs/validation/coupled_box.yaml,
# resin, walls and 30 fibers, 200 steps, about a second) writes three
# snapshots and a checkpoint; then pvpython selects the fibers' blocks at the
# first and last step in both XDMF readers, tools/render.py renders it under
# xvfb-run (PNG not blank, MP4, state file) and tools/report.py summarises it.
set(SPHDEM_BOX_OUT ${CMAKE_CURRENT_BINARY_DIR}/paraview_box_out)
add_test(NAME paraview_box_run
         COMMAND $<TARGET_FILE:sphdem> run ${PROJECT_SOURCE_DIR}/inputs/validation/coupled_box.yaml
                 -q --steps 200 -o ${SPHDEM_BOX_OUT} --overwrite --set output.every_steps=100
                 --checkpoint-every 200)
set_tests_properties(paraview_box_run PROPERTIES LABELS "paraview;tools;cli" TIMEOUT 120
                                                 FIXTURES_SETUP paraview_box_output)
find_program(SPHDEM_PVPYTHON pvpython)
find_program(SPHDEM_XVFB_RUN xvfb-run)
if(SPHDEM_PVPYTHON)
  add_test(NAME paraview_fiber_blocks
           COMMAND ${SPHDEM_PVPYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_paraview_sets.py
                   ${SPHDEM_BOX_OUT}/coupled_box.xdmf fluid,wall,dem,dem_lines 120 90)
  set_tests_properties(paraview_fiber_blocks PROPERTIES LABELS "paraview;io" TIMEOUT 120
                                                        FIXTURES_REQUIRED paraview_box_output)
endif()
if(SPHDEM_PVPYTHON AND SPHDEM_XVFB_RUN)
  add_test(NAME render_png
           COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_render.py render ${SPHDEM_BOX_OUT})
  add_test(NAME report_html
           COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_render.py report ${SPHDEM_BOX_OUT})
  set_tests_properties(render_png report_html PROPERTIES LABELS "paraview;tools" TIMEOUT 300
                                                         FIXTURES_REQUIRED paraview_box_output
                                                         ENVIRONMENT "MPLBACKEND=Agg")
else()
  message(STATUS "pvpython or xvfb-run not found: render_png and report_html are not added")
endif()
