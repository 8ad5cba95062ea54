# The neighbour lists' 16-bit and 32-bit storage (issue 19).
sphdem_test(test_neighbor_storage SOURCES test_neighbor_storage.cpp RANKS 1 LABELS unit)
