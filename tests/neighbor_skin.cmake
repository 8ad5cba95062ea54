# The rebuild test with float positions at the build (issue 19).
sphdem_test(test_neighbor_skin SOURCES test_neighbor_skin.cpp RANKS 1 LABELS unit)
# The skin changes no result, only the rebuilds (issue 19, docs/performance.md
# "The Verlet skin"): channel, dam break, 3D tank and the coupled plate.
sphdem_test(test_skin_results SOURCES test_skin_results.cpp RANKS 1 TIMEOUT 600)
