# A weld line where two melt fronts meet behind an insert (issue 18 part 5,
# docs/paper-comparison.md section 12 "Two fronts meet behind an insert"):
# inputs/insert_melt_front.yaml at 1 mm: weld events in the insert's shadow
# after both streams passed it and nowhere else, and 2 ranks give the 1-rank
# run bitwise (WeldInsertRanks, in the same process).
sphdem_test(test_weld_insert SOURCES test_weld_insert.cpp RANKS 1 2 LABELS validation
            TIMEOUT 300 MULTI_RANK_TESTS "WeldInsertRanks.*" ONE_RANK_TESTS "WeldInsert.*")
