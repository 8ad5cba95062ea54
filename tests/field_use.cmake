# Fields only when used (issue 19, docs/performance.md "Memory per
# particle"): dropped registry fields, their checkpoint columns, and the
# fields each option brings.
sphdem_test(test_field_use SOURCES test_field_use.cpp RANKS 1)
