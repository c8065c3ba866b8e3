# batch_bench: many parameter sets at once (skin::batch) against the single call, side by side
# (issue #12 targets on the 2-core reference machine: 1000 accurate R_d spectra with colours in
# under 1 s on 2 threads; per-set cost of a batch within 1.2x of the single call).
# Run a Release build: build/bin/batch_bench
if(TARGET skin_batch)
  add_executable(batch_bench ${CMAKE_CURRENT_LIST_DIR}/batch_bench.cpp)
  target_link_libraries(batch_bench PRIVATE skin::batch benchmark::benchmark benchmark::benchmark_main)
endif()
