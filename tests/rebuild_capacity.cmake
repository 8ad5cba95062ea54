# Rebuilds keep the particle fields' memory (issue 19, docs/performance.md
# "Rebuilds"): the in-place reordering, the growth margin, and a run whose
# rebuilds after the first allocate no field.
sphdem_test(test_rebuild_capacity SOURCES test_rebuild_capacity.cpp RANKS 1)
