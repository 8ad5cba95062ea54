# The fountain front (issue 18 part 5, docs/physics.md "Viscous traction at
# the free surface", docs/validation.md "Fountain flow"): the free surface's
# viscous traction by hand (a rotating and a sheared block), its implicit
# form (the operator, the small-step limit, the eigenvalues), the channel
# case's front speed, kinematics and shape, and 2 ranks against 1 bitwise,
# explicit and implicit viscosity (FountainRanks, in the same process).
sphdem_test(test_fountain SOURCES test_fountain.cpp RANKS 1 2 LABELS validation TIMEOUT 900
            MULTI_RANK_TESTS "FountainRanks.*"
            ONE_RANK_TESTS "SurfaceTraction.*:Fountain.*")
# The channel with implicit viscosity against the explicit run (two runs to
# 1.5 s, several minutes on a loaded core).
sphdem_test(test_fountain_implicit SOURCES test_fountain_implicit.cpp RANKS 1
            LABELS "validation;long" TIMEOUT 1800)
