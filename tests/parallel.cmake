# Rank-count independence, migration, load balancing and collective output
# (docs/parallel.md): every test compares an N-rank run with a 1-rank run
# computed in the same process.
sphdem_test(test_parallel SOURCES test_parallel.cpp RANKS 1 2 3 4 LABELS mpi TIMEOUT 600)
