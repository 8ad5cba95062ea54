# DEM core (docs/dem.md): unit tests of the pair kernels, loops and fiber
# generator, and validation against docs/validation.md sections 2, 3 and 6.
sphdem_test(test_dem SOURCES test_dem.cpp RANKS 1 LABELS "unit;dem")
sphdem_test(test_dem_validation SOURCES test_dem_validation.cpp RANKS 1 LABELS "validation;dem")
sphdem_test(test_dem_stable_step SOURCES test_dem_stable_step.cpp RANKS 1 LABELS "validation;dem")

# The DEM-only case end to end (inputs/fibers_only.yaml): the paper's 175
# fibers, packed into the bath's top 10 mm so that the piston, sped up to
# 10 m/s, reaches several of them in 20000 DEM steps (0.43 mm of travel,
# about 2 s); then h5py and ParaView read the output.
add_test(NAME fibers_only_run
         COMMAND $<TARGET_FILE:sphdem> run ${PROJECT_SOURCE_DIR}/inputs/fibers_only.yaml -q
                 --steps 20000 -o ${CMAKE_CURRENT_BINARY_DIR}/fibers_only_out --overwrite
                 --set "moving_walls[0].velocity_table=[[0,0,-10]]"
                 --set "fibers.region.box.min=[-0.015,0.050]" --set output.every_steps=10000)
set_tests_properties(fibers_only_run PROPERTIES LABELS "dem;cli" TIMEOUT 120
                                                FIXTURES_SETUP fibers_only_output)
add_test(NAME fibers_only_h5py
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_fibers_only.py
                 ${CMAKE_CURRENT_BINARY_DIR}/fibers_only_out --piston-speed 10)
set_tests_properties(fibers_only_h5py PROPERTIES LABELS "dem;cli;io" TIMEOUT 60
                                                 FIXTURES_REQUIRED fibers_only_output)
find_program(SPHDEM_PVPYTHON pvpython)
if(SPHDEM_PVPYTHON)
  add_test(NAME fibers_only_paraview
           COMMAND ${SPHDEM_PVPYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_fibers_paraview.py
                   ${CMAKE_CURRENT_BINARY_DIR}/fibers_only_out/fibers_only.xdmf 700 525)
  set_tests_properties(fibers_only_paraview PROPERTIES LABELS "dem;cli;io;paraview" TIMEOUT 120
                                                       FIXTURES_REQUIRED fibers_only_output)
endif()
sphdem_test(test_case_fibers SOURCES test_case_fibers.cpp RANKS 1 2 LABELS "unit;dem")

# DEM on 1-4 ranks: bitwise the same as one rank (docs/parallel.md).
# The serial driver's comparison and the double rebuild (contact histories
# kept) run at 1 rank only.
sphdem_test(test_dem_parallel SOURCES test_dem_parallel.cpp RANKS 1 2 3 4 LABELS "mpi;dem"
            TIMEOUT 300 MULTI_RANK_TESTS "DemParallel.*AcrossRanks*"
            ONE_RANK_TESTS
            "DemParallel.SerialDriverMatchesDomain:DemParallel.RebuildBeforeEvaluationKeepsContactHistory")

# The SPH-DEM coupling end to end (docs/physics.md "Coupling").
# The two reference solutions run on one rank; the momentum balance on 1
# and 2 (the drag and its reaction across ranks).
sphdem_test(test_coupled SOURCES test_coupled.cpp RANKS 1 2 LABELS "validation;coupling"
            TIMEOUT 600 ONE_RANK_TESTS "Coupled.TerminalVelocity:Coupled.FiberRelaxation")
sphdem_test(test_coupled_parallel SOURCES test_coupled_parallel.cpp RANKS 2 3 4
            LABELS "mpi;coupling" TIMEOUT 600)

# The short paper plate with its 175 fibers, end to end on 2 ranks (5 ms:
# the piston pushes resin and fibers 4.7 mm); the fibers stay in the mold.
add_test(NAME plate_fibers_short_run
         COMMAND ${MPIEXEC_EXECUTABLE} ${MPIEXEC_NUMPROC_FLAG} 2 ${SPHDEM_MPIEXEC_FLAGS}
                 $<TARGET_FILE:sphdem> run ${PROJECT_SOURCE_DIR}/inputs/plate_fibers_short.yaml -q
                 --overwrite -o ${CMAKE_CURRENT_BINARY_DIR}/plate_fibers_short_out)
set_tests_properties(plate_fibers_short_run PROPERTIES LABELS "case;coupling" TIMEOUT 900 PROCESSORS 2
                                                       FIXTURES_SETUP plate_fibers_short)
add_test(NAME plate_fibers_short_check
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_plate_fibers.py
                 ${CMAKE_CURRENT_BINARY_DIR}/plate_fibers_short_out --fluid 10000 --dem 700
                 --min-drift 1e-3)
set_tests_properties(plate_fibers_short_check PROPERTIES LABELS "case;coupling" TIMEOUT 120
                                                         FIXTURES_REQUIRED plate_fibers_short)

# 3D walls (docs/dem.md, "Walls"): a sphere against a rectangle, the walls'
# checkpoint state, a 3D mold of boxes as rectangles.
sphdem_test(test_dem_walls_3d SOURCES test_dem_walls_3d.cpp RANKS 1 LABELS "unit;dem")
# 2D walls: segment ends that push only when flagged (seams, convex corners
# with one owner), the mold's outline as segments.
sphdem_test(test_dem_walls_2d SOURCES test_dem_walls_2d.cpp RANKS 1 LABELS "unit;dem")

# The 3D DEM-only case end to end (inputs/fibers_only_3d.yaml, 86k steps):
# on 1 and 2 ranks; every fiber stays in the mold of boxes and below the
# piston, and the two runs are bitwise the same (tests/check_fibers_only_3d.py).
add_test(NAME fibers_only_3d_run_np1
         COMMAND $<TARGET_FILE:sphdem> run ${PROJECT_SOURCE_DIR}/inputs/fibers_only_3d.yaml -q
                 -o ${CMAKE_CURRENT_BINARY_DIR}/fibers_only_3d_np1 --overwrite)
add_test(NAME fibers_only_3d_run_np2
         COMMAND ${MPIEXEC_EXECUTABLE} ${MPIEXEC_NUMPROC_FLAG} 2 ${SPHDEM_MPIEXEC_FLAGS}
                 $<TARGET_FILE:sphdem> run ${PROJECT_SOURCE_DIR}/inputs/fibers_only_3d.yaml -q
                 -o ${CMAKE_CURRENT_BINARY_DIR}/fibers_only_3d_np2 --overwrite)
set_tests_properties(fibers_only_3d_run_np1 PROPERTIES LABELS "dem;cli;np1" TIMEOUT 120
                                                       FIXTURES_SETUP fibers_only_3d_output)
set_tests_properties(fibers_only_3d_run_np2 PROPERTIES LABELS "dem;cli;mpi;np2" TIMEOUT 180
                                                       PROCESSORS 2
                                                       FIXTURES_SETUP fibers_only_3d_output)
add_test(NAME fibers_only_3d_check
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_fibers_only_3d.py
                 ${CMAKE_CURRENT_BINARY_DIR}/fibers_only_3d_np1
                 --compare ${CMAKE_CURRENT_BINARY_DIR}/fibers_only_3d_np2)
set_tests_properties(fibers_only_3d_check PROPERTIES LABELS "dem;cli;io" TIMEOUT 60
                                                     FIXTURES_REQUIRED fibers_only_3d_output)
if(SPHDEM_PVPYTHON)
  add_test(NAME fibers_only_3d_paraview
           COMMAND ${SPHDEM_PVPYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_fibers_paraview.py
                   ${CMAKE_CURRENT_BINARY_DIR}/fibers_only_3d_np1/fibers_only_3d.xdmf 160 120)
  set_tests_properties(fibers_only_3d_paraview PROPERTIES LABELS "dem;cli;io;paraview" TIMEOUT 120
                                                          FIXTURES_REQUIRED fibers_only_3d_output)
endif()

# Glass fibers with bond sub-cycling (docs/dem.md, "Bond sub-cycling"):
# against the explicit integrator at E = 72 GPa (a fiber in shear drag,
# the cantilever, a coupled box) and, on 2-4 ranks, bitwise the 1-rank run.
sphdem_test(test_glass_bonds SOURCES test_glass_bonds.cpp RANKS 1 2 3 4 LABELS "validation;dem"
            TIMEOUT 300
            ONE_RANK_TESTS "GlassBonds.SubcycledAndImplicitMatch*:GlassBonds.Cantilever*:GlassBonds.CoupledBoxSubcycledAndImplicitMatchExplicit"
            MULTI_RANK_TESTS "GlassBonds.CoupledBoxRanksAreBitwise")
# `sphdem check` on glass: the explicit bonds' warning and the refusal of a
# DEM longer than a day, both naming fibers.youngs_modulus.
add_test(NAME glass_check_cost
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_glass_cost.py
                 $<TARGET_FILE:sphdem> ${PROJECT_SOURCE_DIR})
set_tests_properties(glass_check_cost PROPERTIES LABELS "dem;cli" TIMEOUT 300)
