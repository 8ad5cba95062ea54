# SPH-DEM coupling (docs/physics.md "Coupling"): the drag law, void fraction,
# Shepard filter, reaction and continuity terms against hand computations,
# and the reference solutions (terminal velocity, relaxation time).
sphdem_test(test_coupling SOURCES test_coupling.cpp RANKS 1 LABELS "unit;coupling")
