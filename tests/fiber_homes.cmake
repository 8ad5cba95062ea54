# Fiber pieces and directions at the fibers' home ranks against the
# gathered version (tests/test_fiber_homes.cpp, docs/checkpoint.md "At scale").
sphdem_test(test_fiber_homes SOURCES test_fiber_homes.cpp RANKS 1 2 3 4 LABELS "unit;dem;mpi")
