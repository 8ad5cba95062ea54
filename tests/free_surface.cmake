# A stable free surface (issue 18 part 2, docs/physics.md "Free surface"):
# detection, particle shifting, the jet-impact
# safeguard and the dam break against Martin & Moyce (1952) (seconds each).
# The dam break's rank independence is in test_parallel
# (RankIndependence.DamBreakFreeSurface).
sphdem_test(test_free_surface SOURCES test_free_surface.cpp RANKS 1 LABELS validation TIMEOUT 600)
# The pass for the anti-clump term alone (issue 19): the same flag and the
# same runs as the full pass (seconds).
sphdem_test(test_free_surface_flag SOURCES test_free_surface_flag.cpp RANKS 1 TIMEOUT 600)

# Issue 18 (Done when): every free-surface case in inputs/validation/ runs
# to its end time at artificial viscosity <= 0.02 (docs/validation.md
# section 12, "Free-surface cases at alpha <= 0.02"). Minutes each on a
# loaded machine: label long, not in CI. The jet is fired at 2.5 m/s, the
# speed of JetImpact.NoResinCrossesTheWall.
foreach(fs_case dam_break dam_break_front hydrostatic_2d hydrostatic_3d weld_line droplet_2d
                droplet_wall_2d jet_impact)
  set(fs_extra)
  if(fs_case STREQUAL "jet_impact")
    set(fs_extra --set "initial_velocity=[-2.5, 0]")
  endif()
  add_test(NAME free_surface_case_${fs_case}
           COMMAND $<TARGET_FILE:sphdem> run -q --overwrite ${fs_extra} -o
                   ${CMAKE_CURRENT_BINARY_DIR}/free_surface_case_${fs_case}_out
                   ${PROJECT_SOURCE_DIR}/inputs/validation/${fs_case}.yaml)
  set_tests_properties(free_surface_case_${fs_case} PROPERTIES TIMEOUT 3600 LABELS "long")
endforeach()
