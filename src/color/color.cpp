#include "skin/color/color.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <ostream>

#include "skin/util/error.hpp"
#include "skin/util/table.hpp"

namespace skin::color {

using skin::util::InputError;
using skin::util::Rgb;
using skin::util::Table;

using skin::physics::Spectrum;
using skin::physics::TabulatedFunction;
using skin::physics::WavelengthGrid;

std::ostream& operator<<(std::ostream& os, const Xyz& c) {
  return os << "XYZ(" << c.X << ", " << c.Y << ", " << c.Z << ')';
}
std::ostream& operator<<(std::ostream& os, const Lab& c) {
  return os << "Lab(" << c.L << ", " << c.a << ", " << c.b << ')';
}

namespace {
const TabulatedFunction& cmf(int c) {
  static const std::array<TabulatedFunction, 3> f = [] {
    const Table& t = util::data::embedded_table("cie1931_2deg_xyz.csv");
    const char* names[3] = {"xbar", "ybar", "zbar"};
    std::array<TabulatedFunction, 3> out;
    for (int i = 0; i < 3; ++i)
      out[static_cast<std::size_t>(i)] =
          TabulatedFunction(t.data[0], t.data[t.column(names[i])], "data/cie1931_2deg_xyz.csv",
                            TabulatedFunction::Outside::zero);
    return out;
  }();
  return f[static_cast<std::size_t>(c)];
}
using Matrix = std::array<std::array<double, 3>, 3>;
Xyz apply(const Matrix& m, const Xyz& c) {
  return {m[0][0] * c.X + m[0][1] * c.Y + m[0][2] * c.Z,
          m[1][0] * c.X + m[1][1] * c.Y + m[1][2] * c.Z,
          m[2][0] * c.X + m[2][1] * c.Y + m[2][2] * c.Z};
}
Matrix multiply(const Matrix& a, const Matrix& b) {
  Matrix m{};
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j)
      for (std::size_t k = 0; k < 3; ++k) m[i][j] += a[i][k] * b[k][j];
  return m;
}
Matrix invert(const Matrix& m) {  // by cofactors; the callers' matrices are well conditioned
  Matrix c{};
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j) {
      const std::size_t i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      c[j][i] = m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1];  // transposed: the adjugate
    }
  const double det = m[0][0] * c[0][0] + m[0][1] * c[1][0] + m[0][2] * c[2][0];
  for (auto& row : c)
    for (auto& v : row) v /= det;
  return c;
}
// The Bradford cone response matrix (Lam 1985, as given in CIE 159:2004 and ICC.1 v4).
constexpr Matrix kBradford{{{0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}}};
}  // namespace

Xyz color_matching(double lambda_nm) { return {cmf(0)(lambda_nm), cmf(1)(lambda_nm), cmf(2)(lambda_nm)}; }

Rgb xyz_to_srgb_linear(const Xyz& c) {
  return {3.2404542 * c.X - 1.5371385 * c.Y - 0.4985314 * c.Z,
          -0.9692660 * c.X + 1.8760108 * c.Y + 0.0415560 * c.Z,
          0.0556434 * c.X - 0.2040259 * c.Y + 1.0572252 * c.Z};
}
Xyz srgb_linear_to_xyz(const Rgb& c) {
  return {0.4124564 * c.r + 0.3575761 * c.g + 0.1804375 * c.b,
          0.2126729 * c.r + 0.7151522 * c.g + 0.0721750 * c.b,
          0.0193339 * c.r + 0.1191920 * c.g + 0.9503041 * c.b};
}

ChromaticAdaptation::ChromaticAdaptation(const Xyz& from, const Xyz& to) : identity_(false) {
  const Xyz s = apply(kBradford, from), d = apply(kBradford, to);
  const Matrix scale{{{d.X / s.X, 0, 0}, {0, d.Y / s.Y, 0}, {0, 0, d.Z / s.Z}}};
  const Matrix back{{{s.X / d.X, 0, 0}, {0, s.Y / d.Y, 0}, {0, 0, s.Z / d.Z}}};
  const Matrix cone_to_xyz = invert(kBradford);
  forward_ = multiply(cone_to_xyz, multiply(scale, kBradford));
  backward_ = multiply(cone_to_xyz, multiply(back, kBradford));
}
Xyz ChromaticAdaptation::operator()(const Xyz& c) const { return identity_ ? c : apply(forward_, c); }
Xyz ChromaticAdaptation::inverse(const Xyz& c) const { return identity_ ? c : apply(backward_, c); }

namespace {
// Colour-matching weights S(lambda) xbar, ybar, zbar on the grid, normalised to sum(S ybar) = 1.
std::vector<std::array<double, 3>> xyz_weights(const WavelengthGrid& grid, const Illuminant& illuminant) {
  std::vector<std::array<double, 3>> w(grid.size());
  double norm = 0.0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const double S = illuminant(grid[i]);
    for (int c = 0; c < 3; ++c) w[i][static_cast<std::size_t>(c)] = S * cmf(c)(grid[i]);
    norm += w[i][1];
  }
  if (!(norm > 0))
    throw InputError("wavelength grid " + std::to_string(grid.lambda_min()) + "-" +
                     std::to_string(grid.lambda_max()) + " nm is out of range: it must overlap " +
                     "the visible range 360-830 nm (and the table of illuminant " +
                     illuminant.name() + ", " + std::to_string(illuminant.table().x_min()) + "-" +
                     std::to_string(illuminant.table().x_max()) + " nm)");
  for (auto& wi : w)
    for (auto& v : wi) v /= norm;
  return w;
}
Xyz white_of(const std::vector<std::array<double, 3>>& w) {
  Xyz c;
  for (const auto& wi : w) {
    c.X += wi[0];
    c.Y += wi[1];
    c.Z += wi[2];
  }
  return c;
}
}  // namespace

Colorimetry::Colorimetry(const WavelengthGrid& grid, const Illuminant& illuminant)
    : grid_(grid), illuminant_(&illuminant), xyz_weights_(xyz_weights(grid, illuminant)) {
  white_ = white_of(xyz_weights_);
  const Illuminant& d65 = find_illuminant(kSrgbWhite);
  // Under D65 no adaptation at all (not a matrix that is the identity only to rounding): the
  // numbers of the default stay what they were.
  if (&illuminant == &d65) {
    d65_white_ = white_;
  } else {
    d65_white_ = white_of(color::xyz_weights(grid, d65));
    adaptation_ = ChromaticAdaptation(white_, d65_white_);
  }
  white_rgb_ = xyz_to_srgb_linear(d65_white_);
  weights_.resize(grid.size());
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const Rgb w = xyz_to_srgb_linear(adaptation_({xyz_weights_[i][0], xyz_weights_[i][1], xyz_weights_[i][2]}));
    weights_[i] = {w.r / white_rgb_.r, w.g / white_rgb_.g, w.b / white_rgb_.b};
  }
}

Rgb Colorimetry::srgb_linear(const Xyz& c) const {
  const Rgb v = xyz_to_srgb_linear(adaptation_(c));
  return {v.r / white_rgb_.r, v.g / white_rgb_.g, v.b / white_rgb_.b};
}

Rgb Colorimetry::illuminant_rgb() const {
  const Rgb w = xyz_to_srgb_linear(white_);
  return {w.r / white_rgb_.r, w.g / white_rgb_.g, w.b / white_rgb_.b};
}

Xyz Colorimetry::xyz(const Spectrum& R) const {
  if (!(R.grid == grid_))
    throw InputError("spectrum grid does not match the colorimetry grid");
  Xyz c;
  for (std::size_t i = 0; i < R.size(); ++i) {
    c.X += xyz_weights_[i][0] * R[i];
    c.Y += xyz_weights_[i][1] * R[i];
    c.Z += xyz_weights_[i][2] * R[i];
  }
  return c;
}

Rgb Colorimetry::srgb_linear(const Spectrum& R) const {
  if (!(R.grid == grid_))
    throw InputError("spectrum grid does not match the colorimetry grid");
  Rgb c;
  for (std::size_t i = 0; i < R.size(); ++i) {
    c.r += weights_[i][0] * R[i];
    c.g += weights_[i][1] * R[i];
    c.b += weights_[i][2] * R[i];
  }
  return c;
}

double srgb_encode(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}
double srgb_decode(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

std::array<int, 3> srgb8(const Rgb& c) {
  std::array<int, 3> out{};
  for (int i = 0; i < 3; ++i)
    out[static_cast<std::size_t>(i)] = static_cast<int>(std::lround(255.0 * srgb_encode(c[i])));
  return out;
}

std::string hex(const std::array<int, 3>& v) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", v[0], v[1], v[2]);
  return buf;
}

Lab xyz_to_lab(const Xyz& c, const Xyz& w) {
  auto f = [](double t) {
    constexpr double e = 216.0 / 24389.0, k = 24389.0 / 27.0;
    return t > e ? std::cbrt(t) : (k * t + 16.0) / 116.0;
  };
  const double fx = f(c.X / w.X), fy = f(c.Y / w.Y), fz = f(c.Z / w.Z);
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

namespace {
// CIEDE2000's weighted differences dL'/S_L, dC'/S_C, dH'/S_H and its rotation term R_T.
struct De2000Terms {
  double L, C, H, RT;
};
De2000Terms delta_e_2000_terms(const Lab& p, const Lab& q) {
  using std::atan2, std::cos, std::sin, std::sqrt, std::pow, std::exp, std::abs;
  constexpr double pi = std::numbers::pi;
  auto deg = [](double r) { return r * 180.0 / pi; };
  auto rad = [](double d) { return d * pi / 180.0; };
  const double C1 = sqrt(p.a * p.a + p.b * p.b), C2 = sqrt(q.a * q.a + q.b * q.b);
  const double Cbar = 0.5 * (C1 + C2);
  const double G = 0.5 * (1.0 - sqrt(pow(Cbar, 7) / (pow(Cbar, 7) + pow(25.0, 7))));
  const double a1 = (1.0 + G) * p.a, a2 = (1.0 + G) * q.a;
  const double C1p = sqrt(a1 * a1 + p.b * p.b), C2p = sqrt(a2 * a2 + q.b * q.b);
  auto hue = [&](double b, double a) {
    if (a == 0 && b == 0) return 0.0;
    double h = deg(atan2(b, a));
    return h < 0 ? h + 360.0 : h;
  };
  const double h1 = hue(p.b, a1), h2 = hue(q.b, a2);
  const double dL = q.L - p.L, dC = C2p - C1p;
  double dh = 0.0;
  if (C1p * C2p != 0) {
    dh = h2 - h1;
    if (dh > 180) dh -= 360;
    else if (dh < -180) dh += 360;
  }
  const double dH = 2.0 * sqrt(C1p * C2p) * sin(rad(dh) / 2.0);
  const double Lbar = 0.5 * (p.L + q.L), Cbarp = 0.5 * (C1p + C2p);
  double hbar = h1 + h2;
  if (C1p * C2p != 0) {
    if (abs(h1 - h2) <= 180) hbar = 0.5 * (h1 + h2);
    else hbar = (h1 + h2 < 360) ? 0.5 * (h1 + h2 + 360) : 0.5 * (h1 + h2 - 360);
  }
  const double T = 1 - 0.17 * cos(rad(hbar - 30)) + 0.24 * cos(rad(2 * hbar)) +
                   0.32 * cos(rad(3 * hbar + 6)) - 0.20 * cos(rad(4 * hbar - 63));
  const double dtheta = 30.0 * exp(-pow((hbar - 275.0) / 25.0, 2));
  const double RC = 2.0 * sqrt(pow(Cbarp, 7) / (pow(Cbarp, 7) + pow(25.0, 7)));
  const double SL = 1 + 0.015 * pow(Lbar - 50, 2) / sqrt(20 + pow(Lbar - 50, 2));
  const double SC = 1 + 0.045 * Cbarp, SH = 1 + 0.015 * Cbarp * T;
  const double RT = -sin(rad(2 * dtheta)) * RC;
  return {dL / SL, dC / SC, dH / SH, RT};
}
}  // namespace

double delta_e_2000(const Lab& p, const Lab& q) {
  using std::pow, std::sqrt;
  const De2000Terms t = delta_e_2000_terms(p, q);
  return sqrt(pow(t.L, 2) + pow(t.C, 2) + pow(t.H, 2) + t.RT * t.C * t.H);
}

std::array<double, 3> delta_e_2000_components(const Lab& p, const Lab& q) {
  // dC^2 + dH^2 + R_T dC dH = (dC + R_T/2 dH)^2 + (1 - R_T^2/4) dH^2 (|R_T| <= 2).
  const De2000Terms t = delta_e_2000_terms(p, q);
  return {t.L, t.C + 0.5 * t.RT * t.H, std::sqrt(std::max(0.0, 1.0 - 0.25 * t.RT * t.RT)) * t.H};
}



ColorSummary summarize_rgb(const Colorimetry& cm, const Rgb& rgb) {
  ColorSummary s;
  s.illuminant = cm.illuminant().name();
  s.srgb_linear = rgb;
  // XYZ consistent with the white-balanced RGB: the grid's D65 white maps to (1, 1, 1); then the
  // adaptation undone (none under D65).
  const Rgb w = xyz_to_srgb_linear(cm.d65_white());
  s.XYZ = cm.adaptation().inverse(srgb_linear_to_xyz({rgb.r * w.r, rgb.g * w.g, rgb.b * w.b}));
  s.srgb8 = srgb8(rgb);
  s.hex = hex(s.srgb8);
  s.lab = xyz_to_lab(s.XYZ, cm.white());
  return s;
}

ColorSummary summarize(const Colorimetry& cm, const Spectrum& R) {
  ColorSummary s = summarize_rgb(cm, cm.srgb_linear(R));
  s.XYZ = cm.xyz(R);
  s.lab = xyz_to_lab(s.XYZ, cm.white());
  return s;
}

RgbVsSpectral rgb_vs_spectral(const Colorimetry& d65, const Colorimetry& under, const Spectrum& R_d) {
  if (!(d65.illuminant().name() == kSrgbWhite) || !(d65.grid() == under.grid()))
    throw InputError("rgb_vs_spectral: the first colorimetry must be D65's, on the same grid");
  RgbVsSpectral r;
  r.rgb_rendering = d65.srgb_linear(R_d) * under.illuminant_rgb();
  // The pixel's XYZ: undo the white balance (D65's white is (1, 1, 1)), then the sRGB matrix.
  const Rgb w = xyz_to_srgb_linear(under.d65_white());
  r.rgb = summarize_xyz(under, srgb_linear_to_xyz(r.rgb_rendering * w));
  r.spectral = summarize(under, R_d);
  r.delta_e_2000 = delta_e_2000(r.spectral.lab, r.rgb.lab);
  return r;
}

ColorSummary summarize_xyz(const Colorimetry& cm, const Xyz& c) {
  ColorSummary s;
  s.illuminant = cm.illuminant().name();
  s.XYZ = c;
  s.srgb_linear = cm.srgb_linear(c);
  s.srgb8 = srgb8(s.srgb_linear);
  s.hex = hex(s.srgb8);
  s.lab = xyz_to_lab(c, cm.white());
  return s;
}

std::ostream& operator<<(std::ostream& os, const ColorSummary& c) {
  return os << "Color{" << c.illuminant << ", " << c.XYZ << ", srgb_linear=" << c.srgb_linear << ", " << c.hex << ", "
            << c.lab << '}';
}

}  // namespace skin::color
