# A stable free surface (issue 18 part 2, docs/physics.md "Free surface"):
# detection, particle shifting, the jet-impact
# safeguard and the dam break against Martin & Moyce (1952) (seconds each).
# The dam break's rank independence is in test_parallel
# (RankIndependence.DamBreakFreeSurface).
sphdem_test(test_free_surface SOURCES test_free_surface.cpp RANKS 1 LABELS validation TIMEOUT 600)
