# Wall conditions and initial fields from expressions (issue 18): validations
# against analytic solutions (seconds each) and the input errors. Their
# rank independence is in test_parallel (RankIndependence.*).
sphdem_test(test_flow_conditions SOURCES test_flow_conditions.cpp RANKS 1 LABELS validation
            TIMEOUT 600)
