# fit_bench: the inverse model (targets on the 2-core reference machine: one spectrum fit
# < 10 ms, a 1024 x 1024 texture < 10 s). Included by bench/CMakeLists.txt.
if(TARGET skin_fit)
  add_executable(fit_bench ${CMAKE_CURRENT_LIST_DIR}/fit_bench.cpp)
  target_link_libraries(fit_bench PRIVATE skin_fit benchmark::benchmark benchmark::benchmark_main)
endif()
