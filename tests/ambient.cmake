# The ambient (air) pressure as a boundary condition (issue 18 parts 2 and 5,
# docs/physics.md "Ambient pressure"): a flat surface by hand, a column at
# rest at 28 B, a decelerating piston with and without the air (seconds
# each), and the plate case at 0.6 mm through a sharp piston deceleration:
# the resin stays on the piston, the front events are written, and 2 ranks
# give the 1-rank run bitwise (PlateFrontRanks, in the same process).
sphdem_test(test_ambient_pressure SOURCES test_ambient_pressure.cpp RANKS 1 2 LABELS validation
            TIMEOUT 600 MULTI_RANK_TESTS "PlateFrontRanks.*"
            ONE_RANK_TESTS "AmbientPressure.*:PlateFront.*")
