# Snapshot output (src/io): the C++ test at 1-3 ranks, then the same files
# read by h5py and by ParaView's two XDMF readers.
sphdem_test(test_io SOURCES test_io.cpp RANKS 1 2 3 LABELS io)

# One run at 3 ranks writes a known snapshot series for the readers below:
# the wall set lives on rank 0, so ranks 1 and 2 write no wall rows.
set(SPHDEM_IO_FIXTURE_DIR ${CMAKE_CURRENT_BINARY_DIR}/io_fixture)
add_test(NAME io_fixture_write
         COMMAND ${MPIEXEC_EXECUTABLE} ${MPIEXEC_NUMPROC_FLAG} 3 ${SPHDEM_MPIEXEC_FLAGS}
                 $<TARGET_FILE:test_io> --gtest_filter=SnapshotWriter.TwoSetsTwoSnapshotsInIdOrder
         WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
set_tests_properties(io_fixture_write PROPERTIES
                     ENVIRONMENT SPHDEM_IO_DIR=${SPHDEM_IO_FIXTURE_DIR}
                     FIXTURES_SETUP io_snapshots PROCESSORS 3 TIMEOUT 120 LABELS "io;np3")

add_test(NAME io_h5py
         COMMAND ${SPHDEM_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_snapshot.py
                 ${SPHDEM_IO_FIXTURE_DIR} --case iotest --snapshots 2
                 --expect fluid=25 --expect wall=7 --test-pattern)
set_tests_properties(io_h5py PROPERTIES FIXTURES_REQUIRED io_snapshots TIMEOUT 120 LABELS io)

find_program(SPHDEM_PVPYTHON pvpython)
if(SPHDEM_PVPYTHON)
  add_test(NAME io_paraview
           COMMAND ${SPHDEM_PVPYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/check_paraview.py
                   ${SPHDEM_IO_FIXTURE_DIR}/iotest.xdmf 25 7 velocity,density --times 2)
  set_tests_properties(io_paraview PROPERTIES FIXTURES_REQUIRED io_snapshots TIMEOUT 300
                                              LABELS "io;paraview")
else()
  message(STATUS "pvpython not found: the io_paraview test is not added")
endif()
