# The distributed set-up (issue 14 part 1, docs/parallel.md "Distributed
# set-up"): each rank's share equals the one-rank set-up's particles in its
# cells, bit for bit.
sphdem_test(test_distributed_setup SOURCES test_distributed_setup.cpp RANKS 1 3 LABELS mpi
            TIMEOUT 120)
