# Generalized-Newtonian resin (issue 13): the laws, their keys and material
# files, and power-law Poiseuille at 1 rank; N ranks bitwise against one.
sphdem_test(test_melt_viscosity SOURCES test_melt_viscosity.cpp RANKS 1 2 LABELS validation
            TIMEOUT 600 MULTI_RANK_TESTS PowerLawPoiseuilleParallel.*
            ONE_RANK_TESTS ViscosityLaw.*:ViscosityKeys.*:PowerLawPoiseuille.*:InjectionPressure.*)
# Implicit viscosity (issue 13 part 3): exact sums, the operator, the CG
# solve, start-up Couette against explicit and the series; N ranks bitwise.
sphdem_test(test_implicit_viscosity SOURCES test_implicit_viscosity.cpp RANKS 1 2 3
            LABELS validation TIMEOUT 300 MULTI_RANK_TESTS ImplicitParallel.*
            ONE_RANK_TESTS ExactSum.*:ViscousOperator.*:ViscousSolve.*:ImplicitCouette.*:ImplicitPoiseuille.*:ImplicitKeys.*)
