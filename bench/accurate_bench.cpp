// Accurate (adding-doubling) solver against the multipole, same inputs, one thread.
//   build/bin/accurate_bench
#include <benchmark/benchmark.h>

#include <cstdio>
#include <memory>
#include <string>

#include "skin/transport/accurate.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/transport/model.hpp"

using namespace skin;
using skin::transport::DiffusionStack;
using skin::transport::ProfileSolver;
using skin::transport::RadialGrid;
using skin::transport::RadialResponse;
using skin::model::skin_diffusion_stacks;
using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;
using skin::physics::find_preset;
using skin::physics::skin_layer_stack;

namespace {
// 0 caucasian, 1 african, 2 caucasian with g 0.8 and index 1.45 (read with the skin table's
// offsets on two axes).
const SkinParameters& params(int preset) {
  static const SkinParameters caucasian = find_preset("caucasian").parameters;
  static const SkinParameters african = find_preset("african").parameters;
  static const SkinParameters other = [] {
    SkinParameters p = find_preset("caucasian").parameters;
    p.g = 0.8;
    p.eta = 1.45;
    return p;
  }();
  return preset == 0 ? caucasian : preset == 1 ? african : other;
}
const char* label(int preset) { return preset == 0 ? "caucasian" : preset == 1 ? "african" : "caucasian g 0.8 eta 1.45"; }
}  // namespace

// R_d(lambda) at 151 wavelengths (400-700 nm, 2 nm): layer optics + adding-doubling per
// wavelength. Arg 0: preset (0 caucasian, 1 african); arg 1: quadrature points per panel.
static void BM_AccurateRdSpectrum(benchmark::State& state) {
  const WavelengthGrid grid;
  const auto& p = params(static_cast<int>(state.range(0)));
  const transport::accurate::Options o{static_cast<int>(state.range(1))};
  const transport::accurate::Cache cache;  // warm after the first iteration, as in the registry's model
  for (auto _ : state) {
    double sum = 0;
    for (std::size_t i = 0; i < grid.size(); ++i)
      sum += transport::accurate::adding_doubling(skin_layer_stack(p, grid[i]), o, cache).R_d;
    benchmark::DoNotOptimize(sum);
  }
  state.SetLabel(label(static_cast<int>(state.range(0))));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(grid.size()));
}
BENCHMARK(BM_AccurateRdSpectrum)
    ->Args({0, 0})
    ->Args({1, 0})
    ->Args({0, 4})
    ->Args({0, 16})
    ->Unit(benchmark::kMillisecond);

// The same with a fresh cache each iteration: the solver's tables (semi-infinite layers, finite
// layers over (omega, tau)) start empty, so this is the cost of a first spectrum.
static void BM_AccurateRdSpectrumColdTables(benchmark::State& state) {
  const WavelengthGrid grid;
  const auto& p = params(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const transport::accurate::Cache cache;
    double sum = 0;
    for (std::size_t i = 0; i < grid.size(); ++i)
      sum += transport::accurate::adding_doubling(skin_layer_stack(p, grid[i]), {}, cache).R_d;
    benchmark::DoNotOptimize(sum);
  }
  state.SetLabel(label(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_AccurateRdSpectrumColdTables)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The multipole on the same inputs, for comparison.
static void BM_MultipoleRdSpectrum(benchmark::State& state) {
  const WavelengthGrid grid;
  const auto& p = params(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    double sum = 0;
    for (std::size_t i = 0; i < grid.size(); ++i)
      sum += DiffusionStack(skin_layer_stack(p, grid[i])).R_d();
    benchmark::DoNotOptimize(sum);
  }
  state.SetLabel(label(static_cast<int>(state.range(0))));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(grid.size()));
}
BENCHMARK(BM_MultipoleRdSpectrum)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// 151 wavelengths -> 3 linear sRGB channels, 512 radii (log-spaced 1 um - 16 mm), as
// skin_bench's BM_RgbProfile does for the multipole: the registry's accurate model's response
// (AccurateStack) per wavelength, then the profile solver (which keeps its quadrature between
// calls).
static void BM_AccurateRgbProfile(benchmark::State& state) {
  const WavelengthGrid grid;
  const auto& p = params(static_cast<int>(state.range(0)));
  ProfileSolver solver(RadialGrid::logarithmic(1e-3, 16.0, 512));
  const auto weights = color::Colorimetry(grid).srgb_weights();
  const transport::Model& model = transport::find_model("accurate");
  auto build = [&] {
    std::vector<std::unique_ptr<RadialResponse>> stacks;
    stacks.reserve(grid.size());
    for (std::size_t i = 0; i < grid.size(); ++i)
      stacks.push_back(model.response(skin_layer_stack(p, grid[i])));
    return stacks;
  };
  auto pointers = [](const std::vector<std::unique_ptr<RadialResponse>>& stacks) {
    std::vector<const RadialResponse*> ptrs;
    for (const auto& s : stacks) ptrs.push_back(s.get());
    return ptrs;
  };
  solver.rgb(pointers(build()), weights);  // warm-up outside the timing: the J0 table, once
  for (auto _ : state) {
    const auto stacks = build();
    benchmark::DoNotOptimize(solver.rgb(pointers(stacks), weights));
  }
  state.SetLabel(label(static_cast<int>(state.range(0))));
  state.counters["nodes"] = static_cast<double>(solver.nodes_used());
}
BENCHMARK(BM_AccurateRgbProfile)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

// The same responses, one profile per wavelength (151 x 512): the "spectral profile".
static void BM_AccurateSpectralProfile(benchmark::State& state) {
  const WavelengthGrid grid;
  const auto& p = params(static_cast<int>(state.range(0)));
  ProfileSolver solver(RadialGrid::logarithmic(1e-3, 16.0, 512));
  const transport::Model& model = transport::find_model("accurate");
  auto run = [&] {
    std::vector<std::unique_ptr<RadialResponse>> stacks;
    std::vector<const RadialResponse*> ptrs;
    for (std::size_t i = 0; i < grid.size(); ++i)
      ptrs.push_back(stacks.emplace_back(model.response(skin_layer_stack(p, grid[i]))).get());
    return solver.spectral(ptrs, grid);
  };
  run();  // warm-up outside the timing: the J0 table, once
  for (auto _ : state) benchmark::DoNotOptimize(run());
  state.SetLabel(label(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_AccurateSpectralProfile)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

static void BM_MultipoleRgbProfile(benchmark::State& state) {
  const WavelengthGrid grid;
  const auto& p = params(static_cast<int>(state.range(0)));
  ProfileSolver solver(RadialGrid::logarithmic(1e-3, 16.0, 512));
  const auto weights = color::Colorimetry(grid).srgb_weights();
  solver.rgb(skin_diffusion_stacks(p, grid), weights);  // warm-up: the J0 table
  for (auto _ : state) {
    const auto stacks = skin_diffusion_stacks(p, grid);
    benchmark::DoNotOptimize(solver.rgb(stacks, weights));
  }
  state.SetLabel(label(static_cast<int>(state.range(0))));
  state.counters["nodes"] = static_cast<double>(solver.nodes_used());
}
BENCHMARK(BM_MultipoleRgbProfile)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// Radiative transfer in the spatial-frequency domain (accurate::FrequencyStack, the model "sfd";
// the accurate model's profile outside its tables): one stack (a preset at 550 nm), and an RGB
// profile of a preset from 7 wavelengths (400-700 nm every 50 nm; the 151 wavelengths
// cost ~21x this, nothing is cached between wavelengths). Iterations(1): each takes seconds.
// Wall time (UseRealTime): the nodes run on every core (TBB), the CPU column counts the calling
// thread only.
static void BM_FrequencyStack(benchmark::State& state) {
  const auto stack = skin_layer_stack(params(static_cast<int>(state.range(0))), 550);
  for (auto _ : state) benchmark::DoNotOptimize(transport::accurate::FrequencyStack(stack).total());
  state.SetLabel(label(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_FrequencyStack)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(2)->UseRealTime();

static void BM_FrequencyRgbProfile(benchmark::State& state) {
  const WavelengthGrid grid(400, 700, 50);
  const auto& p = params(static_cast<int>(state.range(0)));
  ProfileSolver solver(RadialGrid::logarithmic(1e-3, 16.0, 512));
  const auto weights = color::Colorimetry(grid).srgb_weights();
  const transport::Model& model = transport::find_model("sfd");
  for (auto _ : state) {
    std::vector<std::unique_ptr<RadialResponse>> stacks;
    std::vector<const RadialResponse*> ptrs;
    for (std::size_t i = 0; i < grid.size(); ++i) {
      stacks.push_back(model.response(skin_layer_stack(p, grid[i])));
      ptrs.push_back(stacks.back().get());
    }
    benchmark::DoNotOptimize(solver.rgb(ptrs, weights));
  }
  state.SetLabel(label(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_FrequencyRgbProfile)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();

// Issue 31's cases: parameter sets drawn from the whole skin domain (sample_skin_domain(8, 31):
// its edges and corners included), not only the presets. Arg: the draw. The label gives the
// draw's epidermis thickness, g, index and dermis scattering scale, and how many of its 151
// wavelengths the default model solves (off its skin table) rather than reads.
namespace {
const SkinParameters& domain_draw(int i) {
  static const std::vector<SkinParameters> draws = physics::sample_skin_domain(8, 31);
  return draws.at(static_cast<std::size_t>(i));
}
std::string domain_label(int i, const WavelengthGrid& grid) {
  const SkinParameters& p = domain_draw(i);
  char text[160];
  std::snprintf(text, sizeof text, "d %.3g mm, g %.3g, eta %.3g, dermis %.3g, %zu/%zu solved", p.epidermis_thickness,
                p.g, p.eta, p.dermis_scattering_scale,
                model::skin_profile_solves(p, grid, transport::find_model("accurate")), grid.size());
  return text;
}
}  // namespace

// R_d(lambda) at 151 wavelengths of a domain draw (the accurate model's totals, warm tables).
static void BM_DomainRdSpectrum(benchmark::State& state) {
  const WavelengthGrid grid;
  const auto& p = domain_draw(static_cast<int>(state.range(0)));
  const transport::accurate::Cache cache;
  for (auto _ : state) {
    double sum = 0;
    for (std::size_t i = 0; i < grid.size(); ++i)
      sum += transport::accurate::adding_doubling(skin_layer_stack(p, grid[i]), {}, cache).R_d;
    benchmark::DoNotOptimize(sum);
  }
  state.SetLabel(domain_label(static_cast<int>(state.range(0)), grid));
}
BENCHMARK(BM_DomainRdSpectrum)->DenseRange(0, 7)->Unit(benchmark::kMillisecond);

// The RGB profile of a domain draw, as BM_AccurateRgbProfile (151 wavelengths, 512 radii). A
// draw read from the skin table runs for 0.2 s and reports the mean of the warm calls (the
// library's first run, which loads the tables, is not the one reported); a solved draw runs once
// (off the skin table each wavelength is a frequency-domain solve, ~1 min).
static void BM_DomainRgbProfile(benchmark::State& state) {
  const WavelengthGrid grid;
  const auto& p = domain_draw(static_cast<int>(state.range(0)));
  ProfileSolver solver(RadialGrid::logarithmic(1e-3, 16.0, 512));
  for (auto _ : state)
    benchmark::DoNotOptimize(model::skin_rgb_profile(p, grid, solver, transport::find_model("accurate")));
  state.SetLabel(domain_label(static_cast<int>(state.range(0)), grid));
}
BENCHMARK(BM_DomainRgbProfile)->DenseRange(0, 7)->Unit(benchmark::kMillisecond)->MinTime(0.2)->UseRealTime();
