sphdem_test(test_kernel_eos SOURCES test_kernel_eos.cpp RANKS 1 LABELS unit)
sphdem_test(test_geometry SOURCES test_geometry.cpp RANKS 1 LABELS unit)
# The SPH pair terms and the rate loop against hand computations.
sphdem_test(test_sph_terms SOURCES test_sph_terms.cpp RANKS 1 LABELS unit)
# The term registry: selection, record layout, the generated loop against the formulas.
sphdem_test(test_sph_term_registry SOURCES test_sph_term_registry.cpp RANKS 1 LABELS unit)
# Without multiply-add contraction, so that the test of the two forms of the
# pair loop (one particle per lane, one at a time) compares their operations,
# not where GCC chose to fuse a product into an add: with the slot's terms
# inline, GCC -O2 fused differently in the two forms and the density rates
# differed by 1-32 ulp (docs/performance.md, "The plate's loop kept inline;
# the coupling's walks").
target_compile_options(test_sph_term_registry PRIVATE -ffp-contract=off)
# The pair loop's gather: four neighbours at a time bitwise one at a time.
sphdem_test(test_lane_gather SOURCES test_lane_gather.cpp RANKS 1 LABELS unit)
# With AVX also where the library is built without it (the sanitize preset
# builds for generic x86-64), so the four-at-a-time gather runs under the
# sanitizers too; a skip (no AVX on the CPU) shows as skipped, not passed.
target_compile_options(test_lane_gather PRIVATE -mavx)
set_tests_properties(test_lane_gather_np1 PROPERTIES SKIP_REGULAR_EXPRESSION "\\[  SKIPPED \\]")
# The shear-rate pass: exact for linear velocity fields on the lattice.
sphdem_test(test_shear_rate SOURCES test_shear_rate.cpp RANKS 1 LABELS unit)
# Temperature: pairwise conduction by hand and its energy conservation.
sphdem_test(test_heat SOURCES test_heat.cpp RANKS 1 LABELS unit)
# The resin's kick-drift-kick passes: eight particles at a time bitwise one at a time, and by hand.
sphdem_test(test_leapfrog SOURCES test_leapfrog.cpp RANKS 1 LABELS unit)
# The passes eight (or 64) particles at a time: the bits of the one-particle forms, tails included.
sphdem_test(test_particle_lanes SOURCES test_particle_lanes.cpp RANKS 1 LABELS unit)
# The pair loop's compact record: the same runs bitwise as the full record,
# and its conditions checked (src/sph/compact_record.hpp).
sphdem_test(test_compact_record SOURCES test_compact_record.cpp RANKS 1 LABELS unit)
