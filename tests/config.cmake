sphdem_test(test_config SOURCES test_config.cpp RANKS 1 LABELS config)
# NOTE (h-io helper): this file was deleted by mistake at 03:45 UTC and restored
# from the build log's first line; RANKS/LABELS are a guess, please check.
