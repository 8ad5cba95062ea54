# SPH-DEM coupling (docs/physics.md "Coupling"): the drag law, void fraction,
# Shepard filter, reaction and continuity terms against hand computations,
# and the reference solutions (terminal velocity, relaxation time).
sphdem_test(test_coupling SOURCES test_coupling.cpp RANKS 1 LABELS "unit;coupling")

# The coupling passes' pairs kept between passes with a skin: bitwise the
# fresh search's results at every pass, reused while within the skin.
sphdem_test(test_coupling_pairs SOURCES test_coupling_pairs.cpp RANKS 1 LABELS "unit;coupling")

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
set_tests_properties(test_jeffery_np1 PROPERTIES ENVIRONMENT "GTEST_FILTER=-JefferyLong.*")
# The 16-particle chains (about 90 s of CPU): not in CI.
add_test(NAME test_jeffery_long COMMAND test_jeffery --gtest_filter=JefferyLong.*)
set_tests_properties(test_jeffery_long PROPERTIES TIMEOUT 1800 LABELS "long;coupling")

# A fiber carried across the periodic face of a shear cell (sliding walls,
# periodic x, the linear profile at t = 0): bonds intact, 2 ranks bitwise.
sphdem_test(test_shear_cell SOURCES test_shear_cell.cpp RANKS 1 2 TIMEOUT 600 LABELS "validation;coupling")

# Short Jeffery orbits in the 2D and 3D shear cells on the coupled run: 2-4
# ranks bitwise the 1-rank run, which turns at Jeffery's rate within 20 %.
sphdem_test(test_fiber_ranks SOURCES test_fiber_ranks.cpp RANKS 1 2 3 4
            LABELS "validation;coupling" ONE_RANK_TESTS "FiberRanks.JefferyShearCell2D:FiberRanks.JefferyShearCell3D"
            MULTI_RANK_TESTS "FiberRanks.*RanksAreBitwise*")

# A 20-bead fiber in shear stays straight at half the Forgacs-Mason critical
# eta G and buckles at twice it (issue 12 part 5; docs/physics.md "Buckling");
# a stressed seed (fibers.initial_bend) grows only past the threshold.
# The same fiber in a resolved 3D shear cell on the coupled run, seeded: 2-4
# ranks bitwise the 1-rank run (the coupled bracket is test_buckling_long).
sphdem_test(test_buckling SOURCES test_buckling.cpp RANKS 1 2 3 4 LABELS "validation;coupling"
            ONE_RANK_TESTS
            "Buckling.ForgacsMasonBracket3D:Buckling.StressedSeedGrowsOnlyPastThreshold3D:BucklingLong.*:BucklingCoupled.*")
set_tests_properties(test_buckling_np1 PROPERTIES ENVIRONMENT "GTEST_FILTER=-BucklingLong.*:BucklingCoupled.*")
# The seeded bracket on the coupled run, CI-sized (about 15 s of CPU).
add_test(NAME test_buckling_coupled COMMAND test_buckling --gtest_filter=BucklingCoupled.*)
set_tests_properties(test_buckling_coupled PROPERTIES TIMEOUT 900 LABELS "validation;coupling")
add_test(NAME test_buckling_long COMMAND test_buckling --gtest_filter=BucklingLong.*)
set_tests_properties(test_buckling_long PROPERTIES TIMEOUT 3600 LABELS "long;coupling")

# Long fibers (issue 12 part 5): the 20-particle fiber's shear cell is valid
# and runs (300 steps, through the fiber's first turn towards the
# compressional quadrant); at 50 particles it cannot lie in its region:
# `check` exits 2 naming the key and the fiber's length.
add_test(NAME long_fiber_run
         COMMAND $<TARGET_FILE:sphdem> run -q --overwrite --steps 300 -o
                 ${CMAKE_CURRENT_BINARY_DIR}/long_fiber_out
                 ${PROJECT_SOURCE_DIR}/inputs/validation/shear_cell_long_fiber.yaml)
set_tests_properties(long_fiber_run PROPERTIES TIMEOUT 120 LABELS "dem;cli")
add_test(NAME long_fiber_too_long
         COMMAND $<TARGET_FILE:sphdem> check
                 ${PROJECT_SOURCE_DIR}/inputs/validation/shear_cell_long_fiber.yaml --set
                 fibers.particles_per_fiber=50)
set_tests_properties(
  long_fiber_too_long
  PROPERTIES TIMEOUT 60 LABELS "dem;cli" PASS_REGULAR_EXPRESSION
             "key 'fibers.count': fibers: a fiber of 50 particles .* cannot lie in the region")

# The shear cell of test_shear_cell to 0.3 s (about 17,000 steps; it blew up
# at 0.0235 s before the pair list bonded mutually nearest copies): not in CI.
add_test(NAME shear_cell_long
         COMMAND $<TARGET_FILE:sphdem> run -q --overwrite --set numerics.end_time=0.3 -o
                 ${CMAKE_CURRENT_BINARY_DIR}/shear_cell_long_out
                 ${PROJECT_SOURCE_DIR}/inputs/validation/shear_cell.yaml)
set_tests_properties(shear_cell_long PROPERTIES TIMEOUT 1800 LABELS "long;coupling")

# The 3D mold cases' coarse variants (inputs/plate_3d_fibers_coarse.yaml,
# inputs/ribbed_part_fibers_coarse.yaml): 2 ranks bitwise equal to one,
# resin ids conserved, every fiber inside the cavity.
sphdem_test(test_mold3d SOURCES test_mold3d.cpp RANKS 2 LABELS "mpi;coupling" TIMEOUT 300)

# The cluster job of a 3D mold (jobscripts/mold3d_slurm.sh --dry-run): the
# memory per task from `sphdem check --ranks 64`, 64 tasks on 2 nodes.
add_test(NAME mold3d_jobscript
         COMMAND ${PROJECT_SOURCE_DIR}/jobscripts/mold3d_slurm.sh inputs/plate_3d_fibers.yaml
                 ${CMAKE_CURRENT_BINARY_DIR}/mold3d_job 64 --dry-run
         WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
set_tests_properties(
  mold3d_jobscript
  PROPERTIES TIMEOUT 60 LABELS "cli" ENVIRONMENT "SPHDEM=$<TARGET_FILE:sphdem>"
             PASS_REGULAR_EXPRESSION
             "memory: about [0-9.]+ MiB per rank at 64 rank.*64 tasks on 2 node\\(s\\), [0-9]+ MiB per task")
# Exponential drag (fibers.drag_integration: exponential; docs/physics.md
# "Exponential drag"): the two-body exchange, against the drag law and the
# explicit drag at the paper resin's step, and a melt at 2000 fiber drag
# times per step. Ranks: test_coupled_parallel.
sphdem_test(test_exponential_drag SOURCES test_exponential_drag.cpp RANKS 1
            LABELS "validation;coupling" TIMEOUT 300)
