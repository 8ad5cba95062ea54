# The flow front (issue 18 part 5, docs/physics.md "Weld lines and trapped
# air"): the anti-clump term at impacts (the dam break at alpha 0.02
# without shifting), weld lines, a trapped-air pocket, and the events at 1
# and 2 ranks bitwise (FrontEventsRanks, against a 1-rank run in the same
# process).
sphdem_test(test_front SOURCES test_front.cpp RANKS 1 2 LABELS validation TIMEOUT 600
            MULTI_RANK_TESTS "FrontEventsRanks.*"
            ONE_RANK_TESTS "AntiClumpAtImpacts.*:Cavitation.*:WeldLines.*:TrappedAir.*:FrontEvents.*")
