// Monte Carlo throughput: photons per second (items_per_second) for the skin model and for
// generic stacks, side by side, at 1 and 2 threads. Per-core cost = threads / items_per_second.
#include <benchmark/benchmark.h>

#include <ctime>

#include "skin/mc/mc.hpp"
#include "skin/physics/skin_parameters.hpp"

namespace {

void run(benchmark::State& state, const skin::physics::LayerStack& stack, std::uint64_t photons) {
  skin::mc::Options o;
  o.photons = photons;
  o.threads = static_cast<int>(state.range(0));
  std::uint64_t seed = 1;
  // Process CPU time (all threads): the per-core cost, unaffected by other load on the machine.
  const std::clock_t c0 = std::clock();
  for (auto _ : state) {
    o.seed = seed++;
    benchmark::DoNotOptimize(skin::mc::simulate(stack, o).R_d);
  }
  const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  const double total = static_cast<double>(state.iterations()) * static_cast<double>(photons);
  state.SetItemsProcessed(static_cast<std::int64_t>(total));  // wall-clock photons per second
  // CPU seconds per million photons (per core). MCML 1.2.2 side by side: bench/mc_vs_mcml.py.
  state.counters["cpu_s_per_Mphoton"] = cpu / (total / 1e6);
}

// The pale preset of DJ06 Fig. 10 at 650 nm, g = 0.9: long, weakly absorbed paths (the slow case).
void BM_PalePreset650nm(benchmark::State& state) {
  run(state, skin::physics::skin_layer_stack(skin::physics::find_preset("pale").parameters, 650.0), 20000);
}
BENCHMARK(BM_PalePreset650nm)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same at 450 nm: stronger absorption, shorter paths.
void BM_PalePreset450nm(benchmark::State& state) {
  run(state, skin::physics::skin_layer_stack(skin::physics::find_preset("pale").parameters, 450.0), 50000);
}
BENCHMARK(BM_PalePreset450nm)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The MCML paper's matched slab (mu_a = 10/cm, mu_s = 90/cm, g = 0.75, d = 0.02 cm).
void BM_MatchedSlab(benchmark::State& state) {
  skin::physics::LayerStack s;
  s.layers = {skin::physics::Layer{1.0, 2.25, 0.2, 1.0, 0.75}};
  run(state, s, 200000);
}
BENCHMARK(BM_MatchedSlab)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
