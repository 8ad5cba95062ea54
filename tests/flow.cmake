# Wall conditions and initial fields from expressions (issue 18): validations
# against analytic solutions (seconds each) and the input errors. Their
# rank independence is in test_parallel (RankIndependence.*).
sphdem_test(test_flow_conditions SOURCES test_flow_conditions.cpp RANKS 1 LABELS validation
            TIMEOUT 600)
# Surface tension (issue 18 part 3): the continuum surface force against
# hand computations and its input errors (milliseconds); the droplets
# against Laplace and Lamb (seconds); rank independence in test_parallel
# (RankIndependence.Droplet2D).
sphdem_test(test_surface_tension SOURCES test_surface_tension.cpp RANKS 1)
sphdem_test(test_droplet SOURCES test_droplet.cpp RANKS 1 LABELS validation TIMEOUT 600)
