# SPH-DEM coupling (docs/physics.md "Coupling"): the drag law, void fraction,
# Shepard filter, reaction and continuity terms against hand computations,
# and the reference solutions (terminal velocity, relaxation time).
sphdem_test(test_coupling SOURCES test_coupling.cpp RANKS 1 LABELS "unit;coupling")

# The coupling in 3D (inputs/validation/coupled_box_3d.yaml): 2 ranks
# bitwise equal to one, fibers touching the mold's rectangle walls.
sphdem_test(test_coupled_3d SOURCES test_coupled_3d.cpp RANKS 2 LABELS "mpi;coupling"
            TIMEOUT 300)

# The coupled model's stable window (docs/physics.md "Coupling"): a neutrally
# buoyant fiber in a Mach 0.1 shear cell, and a resin spacing finer than
# the fiber's diameter, run stably or are refused by `sphdem check`.
sphdem_test(test_coupled_window SOURCES test_coupled_window.cpp RANKS 1 LABELS "unit;coupling")

# The hydrodynamic torque (docs/physics.md "Hydrodynamic torque"): its kernels,
# the return of angular momentum to the resin, Jeffery orbits of rigid
# chains of 4, 8 and 16 particles in 2D and 3D, and a cloud that keeps flipping.
sphdem_test(test_jeffery SOURCES test_jeffery.cpp RANKS 1 LABELS "validation;coupling")
