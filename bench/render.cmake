# render_bench: the renderer's hot paths (BSSRDF probe sampling, pdf and weight; the profile
# table; the surface term and its rho_dr table; light sampling), camera samples per second on the
# head scene (skipped without the Lee Perry-Smith mesh in ../shared/data) and on the built-in
# default scene with the skin materials and with the same scene made diffuse (target: skin at
# most 2.5x the cost of diffuse), plus the material setup (profiles) and the scene build.
# Included by bench/CMakeLists.txt. Run a Release build: build/bin/render_bench
if(TARGET skin_render)
  add_executable(render_bench ${CMAKE_CURRENT_LIST_DIR}/render_bench.cpp)
  target_link_libraries(render_bench PRIVATE skin::render benchmark::benchmark benchmark::benchmark_main)
  # The internal headers (lights, materials) of the hot paths, as tests/render does.
  target_include_directories(render_bench PRIVATE ${PROJECT_SOURCE_DIR}/src/render)
  target_compile_definitions(render_bench PRIVATE SKIN_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
endif()
# spectral_compare: RGB against spectral rendering (slabs of every preset and a scene under D65
# and A, CIEDE2000; CPU time per sample of each mode). Not a Google Benchmark: a measurement
# for docs/renderer.md. Run: build/bin/spectral_compare examples/head.json docs/figures/spectral-vs-rgb.png
if(TARGET skin_render)
  add_executable(spectral_compare ${CMAKE_CURRENT_LIST_DIR}/spectral_compare.cpp)
  target_link_libraries(spectral_compare PRIVATE skin::render)
  target_include_directories(spectral_compare PRIVATE ${PROJECT_SOURCE_DIR}/src/render)
endif()
