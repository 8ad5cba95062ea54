# Bond stress peaks and broken fibers (issue 12 part 6, docs/dem.md "Bond
# stress peaks", "Broken fibers"): the bookkeeping and the fiber split by
# hand, then a fibers-only run whose bonds break, end to end
# (tests/check_breakage.py): 1 and 2 ranks bitwise, a restart through the
# breaks bitwise, and tools/fiber_lengths.py on its output.
sphdem_test(test_breakage SOURCES test_breakage.cpp RANKS 1 LABELS "unit;dem")
