# `sphdem partition` (docs/scaling.md): the report (gtest) and the command
# line (exit statuses, CSV columns, under mpiexec -n 1 as on a cluster).
sphdem_test(test_partition SOURCES test_partition.cpp RANKS 1 LABELS unit TIMEOUT 120)
# Its weights against a coupled run's: the set-up's parts on two ranks, a
# re-partition's weights with --fiber-substeps.
sphdem_test(test_partition_weights SOURCES test_partition_weights.cpp RANKS 2 LABELS unit
            TIMEOUT 120)

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
# A domain too large for the decomposition's cells (past 2^40): bad input
# (status 2) at the case file's line and key, as `sphdem run` says it.
set(_huge ${CMAKE_CURRENT_BINARY_DIR}/partition_huge_domain.yaml)
add_test(NAME partition_cli_huge_domain
         COMMAND sh -c "cat '${_plate}' > '${_huge}' && \
echo 'domain: {min: [-5.0e3, -5.0e3], max: [5.0e3, 5.0e3]}' >> '${_huge}' && \
line=$(wc -l < '${_huge}') && out=$('$<TARGET_FILE:sphdem>' partition '${_huge}' --ranks 2 2>&1); \
rc=$?; echo \"$out\"; [ $rc -eq 2 ] && \
echo \"$out\" | grep -q \"partition_huge_domain.yaml:$line: key 'domain': .*more than 2^40 cells\"")
# --fiber-substeps: the table says what the work counts; a case without
# fibers is refused (status 2) naming the option.
set(_fibers ${PROJECT_SOURCE_DIR}/inputs/plate_fibers_3.8.yaml)
add_test(NAME partition_cli_fiber_substeps
         COMMAND sh -c "out=$('$<TARGET_FILE:sphdem>' partition '${_fibers}' --ranks 2 \
--fiber-substeps 15 2>&1) || exit 1; echo \"$out\"; echo \"$out\" | grep -q \
'work: 10 per resin, 3 per wall particle with resin in its top-level cell or the next, 1 per other wall particle, 5 x 15 sub-steps = 75 per fiber particle (700 placed)' \
&& out=$('$<TARGET_FILE:sphdem>' partition '${_plate}' --ranks 2 --fiber-substeps 3 2>&1); \
rc=$?; echo \"$out\"; [ $rc -eq 2 ] && echo \"$out\" | grep -q -- '--fiber-substeps.*no fibers'")
set_tests_properties(partition_cli_plate partition_cli_bad_ranks partition_cli_huge_domain
                     partition_cli_fiber_substeps PROPERTIES LABELS "cli" TIMEOUT 120)
