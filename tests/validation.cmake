sphdem_test(test_channel_flows SOURCES test_channel_flows.cpp RANKS 1 LABELS validation TIMEOUT 600)
sphdem_test(test_hydrostatic SOURCES test_hydrostatic.cpp RANKS 1 LABELS validation TIMEOUT 600)
