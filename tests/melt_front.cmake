# The real melt's flow front in the plate (issue 18 part 5,
# docs/paper-comparison.md section 12 "The melt's front"):
# inputs/plate_melt_front.yaml at 1 mm with its nozzle filled, to 8 ms: the
# arms fill across their gap behind an attached front, and 2 ranks give the
# 1-rank run bitwise (MeltFrontRanks, in the same process).
sphdem_test(test_melt_front SOURCES test_melt_front.cpp RANKS 1 2 LABELS validation
            TIMEOUT 300 MULTI_RANK_TESTS "MeltFrontRanks.*" ONE_RANK_TESTS "MeltFront.*")
