sphdem_test(test_channel_flows SOURCES test_channel_flows.cpp RANKS 1 LABELS validation TIMEOUT 600)
sphdem_test(test_hydrostatic SOURCES test_hydrostatic.cpp RANKS 1 LABELS validation TIMEOUT 600)
# Temperature (issue 13 part 2): conduction against erf, Couette with viscous
# heating against Brinkman, the frozen layer against the conduction estimate,
# and the input errors. Rank independence in test_parallel.
sphdem_test(test_thermal SOURCES test_thermal.cpp RANKS 1 LABELS validation TIMEOUT 600)
