# The rebuild test with float positions at the build (issue 19).
sphdem_test(test_neighbor_skin SOURCES test_neighbor_skin.cpp RANKS 1 LABELS unit)
