# Top-level cells of the decomposition (issue 14 part 2, docs/parallel.md):
# block edges, coverage and balance (serial), the same map on every rank.
sphdem_test(test_coarse_partition SOURCES test_coarse_partition.cpp RANKS 1 2 4 LABELS mpi
            TIMEOUT 120 ONE_RANK_TESTS "TopCells.BlockEdge*:TopCells.EveryCell*:TopCells.BlocksAre*")
