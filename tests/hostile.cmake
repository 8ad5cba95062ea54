# Hostile input (issue 15, defects 3, 6, 7, 8): case files refused at
# file:line:key (test_hostile_input), and through the command line
# (tests/check_hostile_input.py): the size guard of check and run, bad
# files, edited checkpoint attributes with nothing deleted.
sphdem_test(test_hostile_input SOURCES test_hostile_input.cpp RANKS 1 LABELS "unit;hostile")
