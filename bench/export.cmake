# export_bench: `skin export` per target and all targets for one parameter set.
if(TARGET skin_export)
  add_executable(export_bench ${CMAKE_CURRENT_SOURCE_DIR}/export_bench.cpp)
  target_link_libraries(export_bench PRIVATE skin::export benchmark::benchmark
    benchmark::benchmark_main)
endif()
