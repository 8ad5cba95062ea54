# DEM core (docs/dem.md): unit tests of the pair kernels, loops and fiber
# generator, and validation against ANALYTIC.md 2, 3 and 6.
sphdem_test(test_dem SOURCES test_dem.cpp RANKS 1 LABELS "unit;dem")
sphdem_test(test_dem_validation SOURCES test_dem_validation.cpp RANKS 1 LABELS "validation;dem")
