# Rank-count independence, migration, load balancing and collective output
# (docs/parallel.md): every test compares an N-rank run with a 1-rank run
# computed in the same process.
# The comparisons with one rank need several ranks; the serial building
# blocks run once, at 1 rank.
sphdem_test(test_parallel SOURCES test_parallel.cpp RANKS 1 2 3 4 LABELS mpi TIMEOUT 600
            MULTI_RANK_TESTS "RankIndependence.*:LoadBalance.*:MeasuredTime.*:Snapshots.*"
            ONE_RANK_TESTS "CellGrid.*:Partition.*")

# Per-step busy times and the lag behind each step's slowest rank
# (docs/parallel.md, "Per-step times").
sphdem_test(test_step_times SOURCES test_step_times.cpp RANKS 1 2 3 LABELS "unit;mpi")
