# accurate_bench: the adding-doubling solver and the accurate radial response, side by side with
# the multipole (issue targets on the 2-core reference machine: accurate R_d spectrum < 5 ms,
# accurate RGB profile < 20 ms). Run a Release build: build/bin/accurate_bench
if(TARGET skin_transport)
  add_executable(accurate_bench ${CMAKE_CURRENT_LIST_DIR}/accurate_bench.cpp)
  find_package(Threads REQUIRED)
  target_link_libraries(accurate_bench PRIVATE skin::transport skin::model Threads::Threads benchmark::benchmark
    benchmark::benchmark_main)
endif()
