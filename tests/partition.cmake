# `sphdem partition` (docs/scaling.md): the report (gtest) and the command
# line (exit statuses, CSV columns, under mpiexec -n 1 as on a cluster).
sphdem_test(test_partition SOURCES test_partition.cpp RANKS 1 LABELS unit TIMEOUT 120)

string(JOIN " " _mpi_flags ${SPHDEM_MPIEXEC_FLAGS})
set(_plate ${PROJECT_SOURCE_DIR}/inputs/plate.yaml)
set(_csv ${CMAKE_CURRENT_BINARY_DIR}/partition_plate.csv)
add_test(NAME partition_cli_plate
         COMMAND sh -c "rm -f '${_csv}' && ${MPIEXEC_EXECUTABLE} -n 1 ${_mpi_flags} \
'$<TARGET_FILE:sphdem>' partition '${_plate}' --ranks 1,2,4 --csv '${_csv}' && \
${SPHDEM_PYTHON} -c \"import csv,sys; r=list(csv.DictReader(open(sys.argv[1]))); \
assert [int(x['ranks']) for x in r]==[1,2,4], r; \
assert all(float(x['imbalance'])<0.2 and float(x['ghost_fraction'])>0 for x in r[1:]), r; \
print('ok', len(r), 'rows')\" '${_csv}'")
add_test(NAME partition_cli_bad_ranks
         COMMAND sh -c "out=$('$<TARGET_FILE:sphdem>' partition '${_plate}' --ranks 4,0 2>&1); \
rc=$?; echo \"$out\"; [ $rc -eq 2 ] && echo \"$out\" | grep -q -- \"--ranks: '0' is not a positive\"")
set_tests_properties(partition_cli_plate partition_cli_bad_ranks PROPERTIES LABELS "cli" TIMEOUT 120)
