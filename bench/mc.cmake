# mc_bench: Monte Carlo photon transport throughput (photons per second) for the pale preset at
# 650 nm with g = 0.9 (the case MCML 1.2 is timed on), one and two threads, and a few variants.
if(TARGET skin_mc)
  add_executable(mc_bench ${CMAKE_CURRENT_LIST_DIR}/mc_bench.cpp)
  target_link_libraries(mc_bench PRIVATE skin_mc benchmark::benchmark benchmark::benchmark_main)
endif()
