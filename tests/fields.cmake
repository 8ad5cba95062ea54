# The field registry (docs/architecture.md, "Adding a field"): a test-only
# registry through ghosts, forward groups, migration, checkpoint columns and
# snapshot fields, at one and two ranks.
sphdem_test(test_fields SOURCES test_fields.cpp RANKS 1 2 LABELS mpi)
