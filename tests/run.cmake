# The run driver (docs/architecture.md, "The run driver"): the case chooses
# the modules of one Run; step, health check and progress are the run's.
sphdem_test(test_run SOURCES test_run.cpp RANKS 1 2 LABELS "unit;dem;coupling")
