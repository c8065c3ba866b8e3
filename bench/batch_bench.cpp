// Many parameter sets: skin::batch::spectra against one skin_spectrum call per set, per set and
// per thread count. 1000 sets sweep melanin 0-0.5 and hemoglobin 0.001-0.1 (skin types from pale
// to dark: the accurate solver's cost varies with the optics). Items are parameter sets.
//   build/bin/batch_bench
#include <benchmark/benchmark.h>

#include "skin/batch/batch.hpp"

using namespace skin;
using skin::transport::RadialGrid;
using skin::model::skin_spectrum;
using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;
using skin::physics::find_preset;

namespace {
std::vector<SkinParameters> sets(std::size_t n) {
  std::vector<SkinParameters> out(n, find_preset("caucasian").parameters);
  for (std::size_t i = 0; i < n; ++i) {
    out[i].melanin = 0.5 * static_cast<double>(i % 50) / 49.0;
    out[i].hemoglobin = 0.001 + 0.099 * static_cast<double>(i / 50) / static_cast<double>((n + 49) / 50);
  }
  return out;
}
const transport::Model& transport_model(std::int64_t which) {
  return transport::find_model(which == 0 ? "accurate" : "multipole");
}
}  // namespace

// The library's single call, one set after another (the cost a batch is compared with).
static void BM_SingleCalls(benchmark::State& state) {
  const auto s = sets(1000);
  const WavelengthGrid grid;
  const transport::Model& m = transport_model(state.range(0));
  for (auto _ : state)
    for (const auto& p : s) benchmark::DoNotOptimize(skin_spectrum(p, grid, m));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(s.size()));
}
BENCHMARK(BM_SingleCalls)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// 1000 sets through skin::batch::spectra on N threads (arg 1); arg 0: accurate / multipole.
static void BM_BatchSpectra(benchmark::State& state) {
  const auto s = sets(1000);
  const WavelengthGrid grid;
  const transport::Model& m = transport_model(state.range(0));
  const batch::Options options{static_cast<int>(state.range(1))};
  for (auto _ : state) benchmark::DoNotOptimize(batch::spectra(s, grid, m, options));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(s.size()));
}
BENCHMARK(BM_BatchSpectra)->Args({0, 1})->Args({0, 2})->Args({1, 1})->Args({1, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime();

// RGB profiles at 64 radii, 100 sets.
static void BM_BatchRgbProfiles(benchmark::State& state) {
  const auto s = sets(100);
  const WavelengthGrid grid;
  const RadialGrid radii = RadialGrid::logarithmic(1e-2, 10.0, 64);
  const batch::Options options{static_cast<int>(state.range(1))};
  for (auto _ : state) benchmark::DoNotOptimize(batch::rgb_profiles(s, grid, radii, transport_model(state.range(0)), options));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(s.size()));
}
BENCHMARK(BM_BatchRgbProfiles)->Args({0, 2})->Args({1, 2})->Unit(benchmark::kMillisecond)->UseRealTime();
