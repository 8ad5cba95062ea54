sphdem_test(test_kernel_eos SOURCES test_kernel_eos.cpp RANKS 1 LABELS unit)
sphdem_test(test_geometry SOURCES test_geometry.cpp RANKS 1 LABELS unit)
sphdem_test(test_sph_terms SOURCES test_sph_terms.cpp RANKS 1 LABELS unit)
