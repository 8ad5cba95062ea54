# Generalized-Newtonian resin (issue 13): the laws, their keys and material
# files, and power-law Poiseuille at 1 rank; N ranks bitwise against one.
sphdem_test(test_melt_viscosity SOURCES test_melt_viscosity.cpp RANKS 1 2 LABELS validation
            TIMEOUT 600 MULTI_RANK_TESTS PowerLawPoiseuilleParallel.*
            ONE_RANK_TESTS ViscosityLaw.*:ViscosityKeys.*:PowerLawPoiseuille.*:InjectionPressure.*)
