# The 3D step's lists cut to the support (issue 19, docs/performance.md
# "The support lists"): the cut against the build's lists, when it is cut
# again, and runs on either lists with the same bits.
sphdem_test(test_support_lists SOURCES test_support_lists.cpp RANKS 1 LABELS unit)
