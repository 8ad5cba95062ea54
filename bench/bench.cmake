add_executable(bench_sph ${CMAKE_CURRENT_LIST_DIR}/bench_sph.cpp)
target_link_libraries(bench_sph PRIVATE sphdem_lib sphdem_warnings)
