// Inverse-model benchmarks. Targets (issue): one spectrum fit < 10 ms, a 1024 x 1024 texture
// < 10 s on the 2-core reference machine. Run a Release build:
//   build/bin/fit_bench
// Each fit runs with the multipole and, where it matters, the adding-doubling forward model.
// Spectrum fits alternate 3 parameters (the paper's), + specular, and the extended model, on a
// synthetic 151-sample spectrum; the fitters' coarse tables are built once outside the timing
// (BM_SpectrumTable times that one-off cost). The texture is synthetic: smooth parameter maps
// rendered to 8-bit colours (about 10^5 distinct colours, like a photographed albedo).
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>

#include "skin/fit/color_fit.hpp"
#include "skin/fit/fit.hpp"
#include "skin/fit/measured.hpp"
#include "skin/model/skin_model.hpp"

using namespace skin;
using skin::model::skin_spectrum;
using skin::physics::SkinParameters;
using skin::physics::WavelengthGrid;
using namespace skin::fit;

namespace {
MeasuredSpectrum synthetic_spectrum() {
  SkinParameters p;
  p.melanin = 0.03;
  p.melanin_blend = 0.4;
  p.hemoglobin = 0.02;
  MeasuredSpectrum m;
  m.name = "bench";
  for (double l = 400; l <= 700; l += 2) m.wavelength_nm.push_back(l);
  m.R = model_reflectance(p, m.wavelength_nm, {});
  for (std::size_t i = 0; i < m.R.size(); ++i) m.R[i] += 0.004 * std::sin(0.37 * static_cast<double>(i));  // "noise"
  return m;
}
const char* solver_name(int s) { return s == 0 ? "multipole" : "accurate"; }
SpectrumFitOptions options(int which, int solver) {
  SpectrumFitOptions o;
  o.model = forward_model(solver_name(solver));
  if (which >= 1) o.includes_specular = true;
  if (which == 2)
    for (Parameter p : extended_parameters()) o.free.push_back(p);
  return o;
}
}  // namespace

// Args: {0 = C_m, beta_m, C_h; 1 = + rho_s (specular); 2 = + all extended terms},
//       {0 = multipole, 1 = accurate (adding-doubling)}.
static void BM_SpectrumFit(benchmark::State& state) {
  const SpectrumFitter fitter(options(static_cast<int>(state.range(0)), static_cast<int>(state.range(1))));
  fitter.prepare();
  const MeasuredSpectrum m = synthetic_spectrum();
  double rms = 0;
  for (auto _ : state) {
    const FitResult r = fitter.fit(m);
    rms = r.rms;
  }
  state.SetLabel("fit rms " + std::to_string(rms));
}
BENCHMARK(BM_SpectrumFit)->Args({0, 0})->Args({1, 0})->Args({2, 0})->Args({0, 1})
    ->Unit(benchmark::kMillisecond)->UseRealTime();

// One-off cost of the global stage's table (paid once per fitter, e.g. once per CLI call).
static void BM_SpectrumTable(benchmark::State& state) {
  for (auto _ : state) {
    const SpectrumFitter fitter;
    fitter.prepare();
  }
}
BENCHMARK(BM_SpectrumTable)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// Arg: 0 = multipole, 1 = accurate.
static void BM_SrgbFit(benchmark::State& state) {
  ColorFitOptions o;
  o.model = forward_model(solver_name(static_cast<int>(state.range(0))));
  const ColorFitter fitter(o);
  fitter.prepare();
  const color::Rgb target = parse_hex("c0a090");
  for (auto _ : state) benchmark::DoNotOptimize(fitter.fit(target).delta_e);
}
BENCHMARK(BM_SrgbFit)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// Whole texture fit, table included (what `skin fit --texture` does after reading the PNG).
// Args: {size}, {0 = multipole, 1 = accurate}.
static Image benchmark_texture(int n);
// The timed loop of both texture benchmarks: a fitter (its table) and the fit of an n x n texture.
static void time_texture_fit(benchmark::State& state, const ColorFitOptions& o, int n) {
  const Image img = benchmark_texture(n);
  double mean = 0;
  for (auto _ : state) {
    const TextureFitter fitter(o);
    const ParameterMaps maps = fitter.fit(img);
    mean = maps.mean_error;
  }
  state.SetLabel("mean dE2000 " + std::to_string(mean));
  state.SetItemsProcessed(state.iterations() * n * n);
}
static void BM_Texture(benchmark::State& state) {
  ColorFitOptions o;
  o.model = forward_model(solver_name(static_cast<int>(state.range(1))));
  time_texture_fit(state, o, static_cast<int>(state.range(0)));
}
BENCHMARK(BM_Texture)->Args({256, 0})->Args({1024, 0})->Args({1024, 1})->Args({4096, 1})->Unit(benchmark::kMillisecond)
    ->UseRealTime()->Iterations(1);

// The same under the extended model (seven free parameters, accurate solver: the built-in table,
// two table solves and two piecewise-polynomial evaluations per distinct colour). Arg: size.
static void BM_TextureExtended(benchmark::State& state) {
  ColorFitOptions o;
  use_fit_model(o, FitModel::extended);
  time_texture_fit(state, o, static_cast<int>(state.range(0)));
}
BENCHMARK(BM_TextureExtended)->Arg(256)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

static Image benchmark_texture(int n) {
  Image img(n, n);
  // Colours from a coarse 64 x 64 grid of parameters, bilinearly blended and quantised to 8 bits.
  const color::Colorimetry cm{WavelengthGrid{}};
  std::vector<color::Rgb> grid(64 * 64);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      SkinParameters p;
      p.melanin = 0.002 * std::pow(150.0, x / 63.0);
      p.melanin_blend = 0.7;
      p.hemoglobin = 0.002 * std::pow(50.0, y / 63.0);
      grid[static_cast<std::size_t>(y * 64 + x)] = skin_spectrum(p, {}, transport::find_model("multipole")).color.srgb_linear;
    }
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double gx = x * 63.0 / (n - 1), gy = y * 63.0 / (n - 1);
      const int x0 = std::min(62, static_cast<int>(gx)), y0 = std::min(62, static_cast<int>(gy));
      const double fx = gx - x0, fy = gy - y0;
      for (int c = 0; c < 3; ++c) {
        auto at = [&](int xx, int yy) { return grid[static_cast<std::size_t>(yy * 64 + xx)][c]; };
        const double v = (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) +
                         fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
        const double q = std::round(color::srgb_encode(v) * 255.0) / 255.0;
        img.rgb[(static_cast<std::size_t>(y) * static_cast<std::size_t>(n) + static_cast<std::size_t>(x)) * 3 +
                   static_cast<std::size_t>(c)] = static_cast<float>(color::srgb_decode(q));
      }
    }
  return img;
}
