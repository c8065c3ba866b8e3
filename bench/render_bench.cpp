// Renderer benchmarks: samples per second on the default scene, skin against diffuse side by
// side (the same geometry, lights and path depth; only the materials differ), and setup costs.
#include <benchmark/benchmark.h>

#include "skin/render/scene.hpp"

namespace {

using skin::render::RenderSettings;
using skin::render::Scene;

// Renders the default scene at 192 x 128, `spp` samples; threads from the argument.
void render_default(benchmark::State& state, bool diffuse) {
  Scene scene = Scene::default_scene();
  if (diffuse) scene.make_translucent_diffuse();
  RenderSettings rs;
  rs.width = 192;
  rs.height = 128;
  rs.spp = 4;
  rs.threads = static_cast<int>(state.range(0));
  std::int64_t samples = 0;
  for (auto _ : state) {
    skin::render::RenderStats stats;
    benchmark::DoNotOptimize(skin::render::render(scene, rs, &stats));
    samples += static_cast<std::int64_t>(stats.camera_samples);
  }
  state.SetItemsProcessed(samples);
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(samples), benchmark::Counter::kIsRate);
}

void BM_DefaultSceneSkin(benchmark::State& state) { render_default(state, false); }
void BM_DefaultSceneDiffuse(benchmark::State& state) { render_default(state, true); }
BENCHMARK(BM_DefaultSceneSkin)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_DefaultSceneDiffuse)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Setup: four skin materials (profiles by inverse Hankel transform) and the Embree build.
void BM_DefaultSceneSetup(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(Scene::default_scene());
}
BENCHMARK(BM_DefaultSceneSetup)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
