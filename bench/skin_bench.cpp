// Core physics benchmarks (issue targets on the 2-core reference machine: R_d spectrum < 0.1 ms,
// RGB profile < 2 ms, full spectral profile < 50 ms). Run a Release build, one thread:
//   build/bin/skin_bench
#include <benchmark/benchmark.h>

#include "skin/model/skin_model.hpp"

using namespace skin;
using skin::transport::DiffusionStack;
using skin::transport::ProfileSolver;
using skin::transport::RadialGrid;
using skin::model::skin_diffusion_stacks;
using skin::model::skin_spectrum;
using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;
using skin::physics::find_preset;
using skin::physics::skin_layer_stack;

namespace {
const SkinParameters& params() {
  static const SkinParameters p = find_preset("caucasian").parameters;
  return p;
}
}  // namespace

// R_d(lambda) at 151 wavelengths (400-700 nm, 2 nm): layer optics + multipole stack at k = 0.
static void BM_RdSpectrum(benchmark::State& state) {
  const WavelengthGrid grid;
  for (auto _ : state) {
    double sum = 0;
    for (std::size_t i = 0; i < grid.size(); ++i)
      sum += DiffusionStack(skin_layer_stack(params(), grid[i])).R_d();
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(grid.size()));
}
BENCHMARK(BM_RdSpectrum)->Unit(benchmark::kMicrosecond);

// Same plus layer coefficients and colour (what `skin spectrum --solver multipole` computes), and
// with the default accurate (adding-doubling) solver.
static void BM_RdSpectrumWithColor(benchmark::State& state) {
  const WavelengthGrid grid;
  for (auto _ : state) benchmark::DoNotOptimize(skin_spectrum(params(), grid, transport::find_model("multipole")));
}
BENCHMARK(BM_RdSpectrumWithColor)->Unit(benchmark::kMicrosecond);
static void BM_RdSpectrumWithColorAccurate(benchmark::State& state) {
  const WavelengthGrid grid;
  for (auto _ : state) benchmark::DoNotOptimize(skin_spectrum(params(), grid, transport::find_model("accurate")));
}
BENCHMARK(BM_RdSpectrumWithColorAccurate)->Unit(benchmark::kMicrosecond);

// 151 wavelengths -> 3 linear sRGB channels, 512 radii (log-spaced 1 um - 16 mm). The solver
// keeps its quadrature between calls, as a renderer building many profiles would.
static void BM_RgbProfile(benchmark::State& state) {
  const WavelengthGrid grid;
  ProfileSolver solver(RadialGrid::logarithmic(1e-3, 16.0, 512));
  const auto weights = color::Colorimetry(grid).srgb_weights();
  for (auto _ : state) {
    const auto stacks = skin_diffusion_stacks(params(), grid);
    benchmark::DoNotOptimize(solver.rgb(stacks, weights));
  }
  state.counters["nodes"] = static_cast<double>(solver.nodes_used());
}
BENCHMARK(BM_RgbProfile)->Unit(benchmark::kMillisecond);

// 151 wavelengths x 512 radii.
static void BM_SpectralProfile(benchmark::State& state) {
  const WavelengthGrid grid;
  ProfileSolver solver(RadialGrid::logarithmic(1e-3, 16.0, 512));
  for (auto _ : state) {
    const auto stacks = skin_diffusion_stacks(params(), grid);
    benchmark::DoNotOptimize(solver.spectral(stacks, grid));
  }
}
BENCHMARK(BM_SpectralProfile)->Unit(benchmark::kMillisecond);

// First call on a new radial grid: includes building the J0 table.
static void BM_RgbProfileColdSolver(benchmark::State& state) {
  const WavelengthGrid grid;
  const auto weights = color::Colorimetry(grid).srgb_weights();
  for (auto _ : state) {
    ProfileSolver solver(RadialGrid::logarithmic(1e-3, 16.0, 512));
    benchmark::DoNotOptimize(solver.rgb(skin_diffusion_stacks(params(), grid), weights));
  }
}
BENCHMARK(BM_RgbProfileColdSolver)->Unit(benchmark::kMillisecond);
