// Spectral rendering's pieces (spectral.hpp; docs/renderer.md, "Spectral rendering").
#include "spectral.hpp"

#include <algorithm>
#include <cmath>

#include "scene_data.hpp"
#include "skin/color/color.hpp"
#include "skin/color/illuminant.hpp"
#include "skin/util/error.hpp"

namespace skin::render {

using skin::physics::WavelengthGrid;

namespace {

constexpr double kRange = kLambdaMax - kLambdaMin;  // [nm]
constexpr int kSteps = static_cast<int>(kRange);     // 1 nm steps of the tables below

// A function of wavelength tabulated at 1 nm over 400-700 nm (301 values), linear between.
double lookup_1nm(const std::vector<double>& t, double lambda) {
  const double x = std::clamp(lambda - kLambdaMin, 0.0, kRange);
  const int i = std::min(static_cast<int>(x), kSteps - 1);
  const double f = x - i;
  return t[static_cast<std::size_t>(i)] * (1 - f) + t[static_cast<std::size_t>(i) + 1] * f;
}
std::vector<double> tabulate_1nm(const auto& f) {
  std::vector<double> t(kSteps + 1);
  for (int i = 0; i <= kSteps; ++i) t[static_cast<std::size_t>(i)] = f(kLambdaMin + i);
  return t;
}
// Integral over 400-700 nm of the product of two such tables (each linear within a step: Simpson
// on each step is exact for the quadratic product).
double integrate_product(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (std::size_t i = 0; i + 1 < a.size(); ++i) {
    const double am = 0.5 * (a[i] + a[i + 1]), bm = 0.5 * (b[i] + b[i + 1]);
    s += (a[i] * b[i] + 4 * am * bm + a[i + 1] * b[i + 1]) / 6.0;
  }
  return s;
}

// The observer and the D65 white at 1 nm, and the white balance of the film.
struct Observer {
  std::array<std::vector<double>, 3> cmf;
  std::vector<double> d65;  // luminance-normalised: integral of d65 x ybar = 1
  Rgb3 white;               // linear sRGB of that white (the division that makes it 1, 1, 1)
  static const Observer& get() {
    static const Observer o;
    return o;
  }

 private:
  Observer() {
    cmf[0] = tabulate_1nm([](double l) { return color::color_matching(l).X; });
    cmf[1] = tabulate_1nm([](double l) { return color::color_matching(l).Y; });
    cmf[2] = tabulate_1nm([](double l) { return color::color_matching(l).Z; });
    const color::Illuminant& D65 = color::find_illuminant(color::kSrgbWhite);
    d65 = tabulate_1nm([&](double l) { return D65(l); });
    const double Y = integrate_product(d65, cmf[1]);
    for (auto& v : d65) v /= Y;
    white = color::xyz_to_srgb_linear({integrate_product(d65, cmf[0]), 1.0, integrate_product(d65, cmf[2])});
  }
};

// Solves the dense system A x = b in place (Gaussian elimination with partial pivoting; the
// systems here are small and well conditioned).
std::vector<double> solve(std::vector<std::vector<double>> A, std::vector<double> b) {
  const std::size_t n = b.size();
  for (std::size_t k = 0; k < n; ++k) {
    std::size_t p = k;
    for (std::size_t i = k + 1; i < n; ++i)
      if (std::abs(A[i][k]) > std::abs(A[p][k])) p = i;
    std::swap(A[k], A[p]);
    std::swap(b[k], b[p]);
    SKIN_ASSERT(A[k][k] != 0, "singular system in the RGB basis fit");
    for (std::size_t i = k + 1; i < n; ++i) {
      const double f = A[i][k] / A[k][k];
      for (std::size_t j = k; j < n; ++j) A[i][j] -= f * A[k][j];
      b[i] -= f * b[k];
    }
  }
  std::vector<double> x(n);
  for (std::size_t k = n; k-- > 0;) {
    double s = b[k];
    for (std::size_t j = k + 1; j < n; ++j) s -= A[k][j] * x[j];
    x[k] = s / A[k][k];
  }
  return x;
}

}  // namespace

SampledWavelengths SampledWavelengths::hero(double u) {
  SampledWavelengths wl;
  for (int j = 0; j < kWavelengths; ++j) {
    double v = u + static_cast<double>(j) / kWavelengths;
    if (v >= 1) v -= 1;
    wl.lambda[static_cast<std::size_t>(j)] = kLambdaMin + kRange * v;
  }
  return wl;
}

RgbUpsampling::RgbUpsampling() {
  // Film colour of the hat function of each grid node: W[c][k] = int hat_k D65 cmf_c / white_c,
  // in linear sRGB (the conversion is linear, so it applies to the weights).
  const Observer& o = Observer::get();
  const WavelengthGrid g = grid();
  const std::size_t n = g.size();
  std::vector<std::array<double, 3>> W(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::vector<double> hat = tabulate_1nm([&](double l) { return std::max(0.0, 1 - std::abs(l - g[k]) / g.step()); });
    std::vector<double> lit(hat.size());
    for (std::size_t i = 0; i < hat.size(); ++i) lit[i] = hat[i] * o.d65[i];
    const Rgb3 c = color::xyz_to_srgb_linear(
        {integrate_product(lit, o.cmf[0]), integrate_product(lit, o.cmf[1]), integrate_product(lit, o.cmf[2])});
    W[k] = {c.r / o.white.r, c.g / o.white.g, c.b / o.white.b};
  }
  // Bands of the box priors: blue below 490 nm, green 490-580 nm, red above (where the sRGB
  // primaries' weights cross over). Smoothness weight alpha on the squared second differences.
  constexpr double kBlueGreen = 490, kGreenRed = 580, kAlpha = 4.0;
  const auto band = [&](double l, int b) {
    return b == 2 ? (l < kBlueGreen ? 1.0 : 0.0) : b == 1 ? (l >= kBlueGreen && l < kGreenRed ? 1.0 : 0.0) : (l >= kGreenRed ? 1.0 : 0.0);
  };
  // cyan = G + B, magenta = R + B, yellow = R + G, red, green, blue (channel masks).
  const std::array<std::array<int, 3>, 6> masks{{{0, 1, 1}, {1, 0, 1}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  // KKT system of min |s - box|^2 + alpha |D2 s|^2 subject to W s = mask: [A W^T; W 0].
  const std::size_t m = n + 3;
  std::vector<std::vector<double>> K(m, std::vector<double>(m, 0.0));
  for (std::size_t i = 0; i < n; ++i) K[i][i] = 1;
  for (std::size_t i = 1; i + 1 < n; ++i) {  // D2 row: s[i-1] - 2 s[i] + s[i+1]
    const std::size_t idx[3] = {i - 1, i, i + 1};
    const double c[3] = {1, -2, 1};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) K[idx[a]][idx[b]] += kAlpha * c[a] * c[b];
  }
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t c = 0; c < 3; ++c) K[n + c][k] = K[k][n + c] = W[k][c];
  for (std::size_t b = 0; b < 6; ++b) {
    std::vector<double> rhs(m, 0.0);
    for (std::size_t k = 0; k < n; ++k)
      for (int c = 0; c < 3; ++c)
        if (masks[b][static_cast<std::size_t>(c)]) rhs[k] += band(g[k], c);
    for (std::size_t c = 0; c < 3; ++c) rhs[n + c] = masks[b][c];
    std::vector<double> x = solve(K, rhs);
    x.resize(n);
    basis_[b] = std::move(x);
  }
}

const RgbUpsampling& RgbUpsampling::get() {
  static const RgbUpsampling u;
  return u;
}

double RgbUpsampling::operator()(const Rgb3& rgb, double lambda) const {
  // Position on the 10 nm grid.
  const double x = std::clamp((lambda - kLambdaMin) / 10.0, 0.0, 30.0);
  const auto i = static_cast<std::size_t>(std::min(x, 29.0));
  const double f = x - static_cast<double>(i);
  const auto at = [&](int k) {
    const auto& b = basis_[static_cast<std::size_t>(k)];
    return b[i] * (1 - f) + b[i + 1] * f;
  };
  enum { cyan, magenta, yellow, red, green, blue };
  const double r = rgb.r, g = rgb.g, b = rgb.b;
  // White for the smallest component, the secondary of the two others for the middle one, the
  // primary of the largest for the rest (Smits 1999).
  if (r <= g && r <= b)
    return g <= b ? r + (g - r) * at(cyan) + (b - g) * at(blue) : r + (b - r) * at(cyan) + (g - b) * at(green);
  if (g <= r && g <= b)
    return r <= b ? g + (r - g) * at(magenta) + (b - r) * at(blue) : g + (b - g) * at(magenta) + (r - b) * at(red);
  return r <= g ? b + (r - b) * at(yellow) + (g - r) * at(green) : b + (g - b) * at(yellow) + (r - g) * at(red);
}

SampledSpectrum RgbUpsampling::operator()(const Rgb3& rgb, const SampledWavelengths& wl) const {
  SampledSpectrum s;
  if (rgb.r == rgb.g && rgb.g == rgb.b) return SampledSpectrum::constant(rgb.r);  // grey: flat
  for (int j = 0; j < kWavelengths; ++j) s[j] = (*this)(rgb, wl.lambda[static_cast<std::size_t>(j)]);
  return s;
}

Rgb3 film_srgb_linear(const SampledSpectrum& L, const SampledWavelengths& wl) {
  const Observer& o = Observer::get();
  color::Xyz c;
  for (int j = 0; j < kWavelengths; ++j) {
    const double l = wl.lambda[static_cast<std::size_t>(j)], v = L[j];
    c.X += v * lookup_1nm(o.cmf[0], l);
    c.Y += v * lookup_1nm(o.cmf[1], l);
    c.Z += v * lookup_1nm(o.cmf[2], l);
  }
  const double w = 1.0 / (kWavelengths * SampledWavelengths::pdf());
  const Rgb3 rgb = color::xyz_to_srgb_linear({c.X * w, c.Y * w, c.Z * w});
  return {rgb.r / o.white.r, rgb.g / o.white.g, rgb.b / o.white.b};
}

SpectralEmission::SpectralEmission(const color::Illuminant* illuminant) {
  const Observer& o = Observer::get();
  if (!illuminant || illuminant->name() == color::kSrgbWhite) {
    spd_ = o.d65;
    return;
  }
  spd_ = tabulate_1nm([&](double l) { return (*illuminant)(l); });
  const double Y = integrate_product(spd_, o.cmf[1]);
  SKIN_ASSERT(Y > 0, "illuminant without luminance over 400-700 nm");
  for (auto& v : spd_) v /= Y;
  // What the RGB render multiplied the light's value by (scene.cpp: Colorimetry::illuminant_rgb
  // on the materials' grid); divided out here so that the value is upsampled alone.
  illuminant_rgb_ = color::Colorimetry(WavelengthGrid(), *illuminant).illuminant_rgb();
  white_ = false;
}

double SpectralEmission::spd(double lambda) const { return lookup_1nm(spd_, lambda); }

SampledSpectrum SpectralEmission::operator()(const Rgb3& L, const SampledWavelengths& wl) const {
  const Rgb3 value = white_ ? L : Rgb3{L.r / illuminant_rgb_.r, L.g / illuminant_rgb_.g, L.b / illuminant_rgb_.b};
  SampledSpectrum s = RgbUpsampling::get()(value, wl);
  for (int j = 0; j < kWavelengths; ++j) s[j] *= spd(wl.lambda[static_cast<std::size_t>(j)]);
  return s;
}

std::array<ProfileChannel, kWavelengths> SpectralSkin::channels(const SampledWavelengths& wl) const {
  std::array<ProfileChannel, kWavelengths> ch;
  const double last = static_cast<double>(grid.size() - 1);
  for (std::size_t j = 0; j < ch.size(); ++j) {
    const double x = std::clamp((wl.lambda[j] - grid.lambda_min()) / grid.step(), 0.0, last);
    const auto i = static_cast<std::size_t>(std::min(x, last - 1));
    ch[j] = ProfileChannel(profile[i], profile[i + 1], x - static_cast<double>(i));
  }
  return ch;
}

double SpectralCurve::operator()(double lambda) const {
  const double last = static_cast<double>(grid.size() - 1);
  const double x = std::clamp((lambda - grid.lambda_min()) / grid.step(), 0.0, last);
  const auto i = static_cast<std::size_t>(std::min(x, last - 1));
  const double f = x - static_cast<double>(i);
  return values[i] * (1 - f) + values[i + 1] * f;
}

}  // namespace skin::render
