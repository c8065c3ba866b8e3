// Real time: a sum of Gaussians (fit_gaussians) and a separable screen-space kernel, as JSON
// (docs/export.md, "Real-time and tables").
#include <algorithm>
#include <cmath>
#include <numbers>

#include "fits.hpp"
#include "report.hpp"

namespace skin::exporting::detail {

using skin::util::Rgb;

namespace {

Export write(const Context& ctx) {
  const Reference& ref = ctx.ref;
  const Options& o = ctx.options;
  const Unit unit = ctx.unit;
  const Gaussians g = fit_gaussians(ref, o.gaussians);
  Rgb R_d_t;
  for (int c = 0; c < 3; ++c)
    for (double w : g.w[c]) R_d_t[c] += w;
  const double scale = ctx.scale();
  Export e;
  e.report = fit_report(
      ctx,
      "sum of Gaussians with shared variances (d'Eon et al. 2007) and a "
      "separable screen-space kernel (Jimenez et al. 2015)",
      R_d_t, g.R);
  json j = document_head("Spectral Skin export: real-time subsurface kernels", o);
  j["units"] = {{"variance", std::string(unit_name(unit)) + "^2"},
                {"offset", std::string(unit_name(unit))}};
  j["R_d"] = vec(ref.R_d);
  json gs = json::array();
  for (int k = 0; k < o.gaussians; ++k)
    gs.push_back({{"variance", g.v[k] * scale * scale},
                  {"weight", {g.w[0][k], g.w[1][k], g.w[2][k]}}});
  j["gaussians"] = gs;
  j["gaussian_definition"] =
      "R(r) = sum_k weight_k exp(-r^2 / (2 variance_k)) / (2 pi variance_k); the weights sum to "
      "R_d per channel";
  // Separable kernel: taps x_i = range sign(t) t^2 over t evenly in [-1, 1], range = 3 sigma of
  // the widest Gaussian; weights = the 1-D marginal of the Gaussian sum times each tap's
  // interval, normalised to 1 per channel (the albedo multiplies separately).
  const double v_max = *std::max_element(g.v.begin(), g.v.end());
  const double range = 3.0 * std::sqrt(v_max);
  const int N = o.taps;
  std::vector<double> x(N);
  for (int i = 0; i < N; ++i) {
    const double t = -1.0 + 2.0 * i / (N - 1);
    x[i] = range * (t < 0 ? -1 : 1) * t * t;
  }
  std::array<std::vector<double>, 3> w;
  for (int c = 0; c < 3; ++c) {
    w[c].resize(N);
    double sum = 0;
    for (int i = 0; i < N; ++i) {
      const double lo = i == 0 ? x[0] : 0.5 * (x[i - 1] + x[i]);
      const double hi = i == N - 1 ? x[N - 1] : 0.5 * (x[i] + x[i + 1]);
      double marginal = 0;
      for (int k = 0; k < o.gaussians; ++k)
        marginal += g.w[c][k] * std::exp(-x[i] * x[i] / (2 * g.v[k])) / std::sqrt(2 * std::numbers::pi * g.v[k]);
      w[c][i] = marginal * std::max(hi - lo, 1e-12);
      sum += w[c][i];
    }
    for (double& v : w[c]) v = sum > 0 ? v / sum : 0.0;
  }
  json taps = json::array();
  for (int i = 0; i < N; ++i)
    taps.push_back({{"offset", x[i] * scale}, {"weight", {w[0][i], w[1][i], w[2][i]}}});
  j["separable_kernel"] = {{"taps", taps},
                           {"definition", "apply horizontally then vertically in screen space "
                                          "with offsets scaled by the pixels per unit at the "
                                          "surface; weights sum to 1 per channel"}};
  e.report.values = {{"variances", [&] {
                        std::vector<double> v;
                        for (double x2 : g.v) v.push_back(x2 * scale * scale);
                        return v;
                      }()}};
  e.files.push_back({"", rounded(j).dump(2) + "\n", false});
  return e;
}

}  // namespace

TargetSpec realtime_target() {
  return {"realtime", "sum-of-Gaussians fit and a separable screen-space kernel (JSON)", ".json",
          Unit::mm, write};
}

}  // namespace skin::exporting::detail
