// Colour fit (exact model) and texture fit (interpolated table), docs/fit.md.
#include "skin/fit/color_fit.hpp"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <limits>
#include <mutex>
#include <ostream>

#include <Eigen/Dense>
#include <tbb/parallel_for.h>

#include "lm.hpp"
#include "skin/util/cancel.hpp"
#include "skin/util/error.hpp"
#include "skin/util/table.hpp"

namespace skin::fit {

using skin::util::InputError;
using skin::util::ProgressCallback;
using skin::util::format_number;
using skin::util::require_in_range;
using skin::util::require_non_negative;

using skin::physics::SkinParameters;

std::ostream& operator<<(std::ostream& os, const ColorFitResult& r) {
  return os << "ColorFitResult{C_m=" << r.parameters.melanin << ", beta_m=" << r.parameters.melanin_blend
            << ", C_h=" << r.parameters.hemoglobin << ", target=" << r.target << ", fitted=" << r.fitted
            << ", dE2000=" << r.delta_e << ", iterations=" << r.iterations << '}';
}

std::ostream& operator<<(std::ostream& os, const ParameterMaps& m) {
  return os << "ParameterMaps{" << m.width << "x" << m.height << ", mean dE=" << m.mean_error
            << ", max dE=" << m.max_error << ", below 1: " << m.fraction_below_1 << '}';
}

namespace {

double parse_number(const std::string& what, const std::string& s) {
  std::size_t used = 0;
  double v = std::numeric_limits<double>::quiet_NaN();
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != s.size() || !std::isfinite(v))
    throw InputError(what + " = '" + s + "' is not a number");
  return v;
}

}  // namespace

color::Rgb parse_srgb8(const std::string& text) {
  std::vector<std::string> parts;
  std::size_t pos = 0;
  while (true) {
    const std::size_t comma = text.find(',', pos);
    parts.push_back(text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos));
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  if (parts.size() != 3)
    throw InputError("srgb = '" + text + "' must be three numbers R,G,B (8-bit sRGB, 0-255)");
  double v[3];
  for (int c = 0; c < 3; ++c) {
    v[c] = parse_number("srgb", parts[static_cast<std::size_t>(c)]);
    require_in_range("srgb", v[c], 0.0, 255.0);
  }
  return {color::srgb_decode(v[0] / 255.0), color::srgb_decode(v[1] / 255.0),
          color::srgb_decode(v[2] / 255.0)};
}

color::Rgb parse_hex(const std::string& text) {
  std::string s = text;
  if (!s.empty() && s.front() == '#') s.erase(0, 1);
  const bool ok = s.size() == 6 && std::all_of(s.begin(), s.end(), [](char c) {
                    return std::isxdigit(static_cast<unsigned char>(c)) != 0;
                  });
  if (!ok) throw InputError("hex = '" + text + "' must be six hexadecimal digits RRGGBB");
  double v[3];
  for (int c = 0; c < 3; ++c) v[c] = std::stoi(s.substr(static_cast<std::size_t>(2 * c), 2), nullptr, 16);
  return {color::srgb_decode(v[0] / 255.0), color::srgb_decode(v[1] / 255.0),
          color::srgb_decode(v[2] / 255.0)};
}

// ---------------------------------------------------------------------------------------------
// ColorFitter

struct ColorFitter::Impl {
  ColorFitOptions opt;
  ForwardModel model;
  color::Colorimetry cm;
  std::vector<double> lambda;
  bool fit_blend = false;

  explicit Impl(ColorFitOptions o) : opt(std::move(o)), cm(opt.grid), lambda(opt.grid.values()) {}

  Bounds bounds_of(Parameter p) const {
    for (const auto& [q, b] : opt.bounds)
      if (q == p) return b;
    return opt.fit_model == FitModel::extended ? prior_bounds(p) : default_bounds(p);
  }
  bool extended() const { return opt.fit_model == FitModel::extended; }

  // Lab of linear (white-balanced) sRGB, the way `skin color` reports it.
  color::Lab lab_of(const color::Rgb& rgb) const { return color::summarize_rgb(cm, rgb).lab; }

  // Model colour as white-balanced linear sRGB (the colour weights are linear in R_d).
  color::Rgb rgb(const SkinParameters& p) const {
    const auto& w = cm.srgb_weights();
    color::Rgb c;
    for (std::size_t i = 0; i < lambda.size(); ++i) {
      const double R = model(p, lambda[i]);
      c.r += w[i][0] * R;
      c.g += w[i][1] * R;
      c.b += w[i][2] * R;
    }
    return c;
  }
  color::Lab lab(const SkinParameters& p) const { return lab_of(rgb(p)); }

  // Coarse table for the starting point.
  mutable std::once_flag once;
  mutable std::vector<SkinParameters> table_p;
  mutable std::vector<color::Lab> table_lab;
  void build_table() const {
    std::vector<std::vector<double>> axes;
    for (Parameter p : {Parameter::melanin, Parameter::melanin_blend, Parameter::hemoglobin}) {
      std::vector<double> v;
      const bool free = std::find(opt.free.begin(), opt.free.end(), p) != opt.free.end();
      const Bounds b = bounds_of(p);
      if (!free) v.push_back(get(opt.start, p));
      else if (p == Parameter::melanin_blend) for (int i = 0; i <= 4; ++i) v.push_back(b.lo + (b.hi - b.lo) * i / 4.0);
      else {
        const double a = std::max(b.lo, b.hi * 2e-3);
        if (b.lo < a) v.push_back(b.lo);
        for (int i = 0; i < 12; ++i) v.push_back(a * std::pow(b.hi / a, i / 11.0));
      }
      axes.push_back(v);
    }
    for (double m : axes[0])
      for (double bl : axes[1])
        for (double h : axes[2]) {
          SkinParameters p = opt.start;
          p.melanin = m;
          p.melanin_blend = bl;
          p.hemoglobin = h;
          table_p.push_back(p);
        }
    table_lab.resize(table_p.size());
    // A cancelled build throws out of call_once (prepare()), which then builds again next time.
    tbb::parallel_for(std::size_t(0), table_p.size(), [&](std::size_t i) {
      if (!util::cancel::requested()) table_lab[i] = lab(table_p[i]);
    });
    util::cancel::check();
  }
};

ColorFitter::ColorFitter(ColorFitOptions options) {
  options.start.validate();
  require_non_negative("melanin-blend-weight", options.melanin_blend_weight);
  require_in_range("melanin-blend-prior", options.melanin_blend_prior, 0.0, 1.0);
  if (options.free.empty()) throw InputError("free parameters: the list is empty");
  check_bounds(options.bounds);
  for (std::size_t i = 0; i < options.free.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (options.free[i] == options.free[j])
        throw InputError("free parameter '" + flag(options.free[i]) + "' is listed twice");
  for (Parameter p : options.free)
    if (options.fit_model != FitModel::extended && p != Parameter::melanin && p != Parameter::melanin_blend &&
        p != Parameter::hemoglobin)
      throw InputError("free parameter '" + flag(p) +
                       "' cannot be fitted from a colour by the paper model: choose among melanin, "
                       "melanin-blend, hemoglobin, or use --model extended");
    else if (p == Parameter::oiliness)
      throw InputError("free parameter 'oiliness' (rho_s) does not enter R_d: it cannot be fitted from a colour");
  impl_ = std::make_unique<Impl>(std::move(options));
  impl_->model = impl_->opt.model ? impl_->opt.model : forward_model(transport::default_model());
  impl_->fit_blend = std::find(impl_->opt.free.begin(), impl_->opt.free.end(), Parameter::melanin_blend) !=
                     impl_->opt.free.end();
  for (Parameter p : impl_->opt.free) {
    const Bounds b = impl_->bounds_of(p);
    if (!(b.lo < b.hi)) throw InputError("bounds of " + flag(p) + " are invalid: need lo < hi");
    if (impl_->extended() && has_prior_centre(p)) set(impl_->opt.start, p, p.info().prior_centre);
    set(impl_->opt.start, p, std::clamp(get(impl_->opt.start, p), b.lo, b.hi));
  }
  {
    SkinParameters lo = impl_->opt.start, hi = impl_->opt.start;
    for (Parameter p : impl_->opt.free) set(lo, p, impl_->bounds_of(p).lo), set(hi, p, impl_->bounds_of(p).hi);
    lo.validate();
    hi.validate();
  }
}
ColorFitter::~ColorFitter() = default;
ColorFitter::ColorFitter(ColorFitter&&) noexcept = default;
ColorFitter& ColorFitter::operator=(ColorFitter&&) noexcept = default;
const ColorFitOptions& ColorFitter::options() const { return impl_->opt; }
void ColorFitter::prepare() const { std::call_once(impl_->once, [this] { impl_->build_table(); }); }
color::Lab ColorFitter::lab(const SkinParameters& p) const { return impl_->lab(p); }

ColorFitResult ColorFitter::fit(const color::Rgb& target_rgb) const {
  for (int c = 0; c < 3; ++c) require_in_range("srgb (linear)", target_rgb[c], 0.0, 1.0);
  prepare();
  const Impl& m = *impl_;
  const color::Lab target = m.lab_of(target_rgb);
  const double w = m.opt.melanin_blend_weight, prior = m.opt.melanin_blend_prior;
  auto objective = [&](const color::Lab& l, double blend) {
    const double dL = l.L - target.L, da = l.a - target.a, db = l.b - target.b;
    const double reg = m.fit_blend && !m.extended() ? w * (blend - prior) : 0.0;
    return dL * dL + da * da + db * db + reg * reg;
  };
  std::size_t best = 0;
  double best_cost = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < m.table_p.size(); ++i) {
    const double c = objective(m.table_lab[i], m.table_p[i].melanin_blend);
    if (c < best_cost) best_cost = c, best = i;
  }
  const std::vector<Parameter>& which = m.opt.free;
  const auto n = static_cast<Eigen::Index>(which.size());
  // Extended: the Gaussian prior terms of the free parameters that have a prior centre.
  std::vector<Parameter> priors;
  if (m.extended())
    for (Parameter q : which)
      if (has_prior_centre(q)) priors.push_back(q);
  detail::LmProblem prob;
  prob.m = m.extended() ? 3 + static_cast<Eigen::Index>(priors.size()) : (m.fit_blend ? 4 : 3);
  prob.lo.resize(n);
  prob.hi.resize(n);
  prob.h.resize(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const Bounds b = m.bounds_of(which[j]);
    prob.lo[j] = b.lo;
    prob.hi[j] = b.hi;
    prob.h[j] = 1e-6 * (b.hi - b.lo);
  }
  SkinParameters p = m.opt.start;
  prob.residual = [&](const Eigen::VectorXd& x, Eigen::VectorXd& r) {
    SkinParameters q = m.opt.start;
    for (Eigen::Index j = 0; j < n; ++j) set(q, which[j], x[j]);
    const color::Lab l = m.lab(q);
    if (m.extended()) {
      const auto d = color::delta_e_2000_components(target, l);
      r[0] = d[0], r[1] = d[1], r[2] = d[2];
      for (std::size_t k = 0; k < priors.size(); ++k) {
        const Parameter pk = priors[k];
        r[3 + static_cast<Eigen::Index>(k)] =
            kColorPriorWeight * (prior_coordinate(pk, get(q, pk)) - prior_coordinate(pk, pk.info().prior_centre));
      }
      return;
    }
    r[0] = l.L - target.L;
    r[1] = l.a - target.a;
    r[2] = l.b - target.b;
    if (m.fit_blend) r[3] = w * (q.melanin_blend - prior);
  };
  // Starts: the best table entry; the extended model also the next two best with another melanin
  // (six unknowns: the valley of equal colours has several basins).
  std::vector<std::size_t> starts = {best};
  if (m.extended()) {
    std::vector<std::pair<double, std::size_t>> ranked;
    for (std::size_t i = 0; i < m.table_p.size(); ++i)
      ranked.emplace_back(objective(m.table_lab[i], m.table_p[i].melanin_blend), i);
    std::sort(ranked.begin(), ranked.end());
    for (const auto& [c, i] : ranked) {
      if (starts.size() >= 3) break;
      bool other = std::isfinite(c);
      for (std::size_t s : starts) other = other && m.table_p[s].melanin != m.table_p[i].melanin;
      if (other) starts.push_back(i);
    }
  }
  detail::LmResult res;
  for (std::size_t k = 0; k < starts.size(); ++k) {
    Eigen::VectorXd x0(n);
    for (Eigen::Index j = 0; j < n; ++j) x0[j] = std::clamp(get(m.table_p[starts[k]], which[j]), prob.lo[j], prob.hi[j]);
    detail::LmResult rk = detail::levenberg_marquardt(prob, x0, 50, true);
    if (k == 0 || rk.cost < res.cost) res = std::move(rk);
  }
  for (Eigen::Index j = 0; j < n; ++j) set(p, which[j], res.x[j]);
  ColorFitResult out;
  out.parameters = p;
  out.target = target;
  out.fitted_srgb_linear = m.rgb(p);
  out.fitted = m.lab_of(out.fitted_srgb_linear);
  out.delta_e = color::delta_e_2000(target, out.fitted);
  out.iterations = res.iterations;
  out.fit_model = m.opt.fit_model;
  out.outside_gamut = out.delta_e > kGamutDeltaE;
  out.free = which;
  // Covariance (J^T J)^-1 for residuals of unit variance (a target known to one Lab or CIEDE2000
  // unit per component); the prior rows are part of J.
  const Eigen::VectorXd se = detail::standard_errors_scaled(res.J, 1.0);
  for (Eigen::Index j = 0; j < n; ++j) {
    out.uncertainty.push_back(se[j]);
    const double span = prob.hi[j] - prob.lo[j];
    out.at_bound.push_back(res.x[j] <= prob.lo[j] + 1e-9 * span || res.x[j] >= prob.hi[j] - 1e-9 * span);
  }
  return out;
}

namespace {
std::string shortest(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}
}  // namespace

std::string ColorTable::to_csv(std::string_view provenance) const {
  std::string out =
      "# Spectral Skin: a texture fit's colour table (skin fit --texture; the provenance names the model and\n"
      "# solver): CIELAB under D65 of R_d every 10 nm, linearly interpolated to 400-700 nm every 2 nm\n"
      "# (TextureFitter::node_lab), at every node of a grid over the free parameters: per parameter `nodes`\n"
      "# values evenly spaced from lo to hi (in log(value + offset) where log is 1, else in the value),\n"
      "# row-major, the last free parameter fastest; the other parameters at the fixed.* values.\n"
      "# include/skin/fit/color_fit.hpp, docs/fit.md.\n";
  out += "# provenance: " + std::string(provenance) + "\n";
  std::string keys, lo, hi, n, lg, off;
  for (std::size_t k = 0; k < free.size(); ++k) {
    if (k) keys += ',', lo += ',', hi += ',', n += ',', lg += ',', off += ',';
    keys += key(free[k]);
    lo += shortest(bounds[k].lo);
    hi += shortest(bounds[k].hi);
    n += std::to_string(nodes[k]);
    lg += log[k] ? '1' : '0';
    off += shortest(offset[k]);
  }
  out += "# free: " + keys + "\n# lo: " + lo + "\n# hi: " + hi + "\n# nodes: " + n + "\n# log: " + lg +
         "\n# offset: " + off + "\n";
  for (const physics::ParameterInfo& row : physics::parameter_table())
    if (std::find_if(free.begin(), free.end(), [&](Parameter p) { return &p.info() == &row; }) == free.end())
      out += "# fixed." + std::string(row.key) + ": " + shortest(fixed.*(row.member)) + "\n";
  out += "L,a,b\n";
  // (A node the model cannot evaluate, NaN, is an empty field.)
  auto field = [](double v) { return std::isfinite(v) ? shortest(v) : std::string(); };
  for (const color::Lab& l : lab) out += field(l.L) + "," + field(l.a) + "," + field(l.b) + "\n";
  return out;
}

ColorTable ColorTable::parse(std::string_view text, const std::string& source) {
  const auto meta = util::csv_metadata(text);
  const auto it = meta.find("free");
  if (it == meta.end()) throw InputError(source + ": missing the '# free:' line");
  ColorTable t;
  t.free = parse_parameter_list(it->second);
  const auto lo = util::metadata_numbers(meta, "lo", source), hi = util::metadata_numbers(meta, "hi", source),
             n = util::metadata_numbers(meta, "nodes", source), lg = util::metadata_numbers(meta, "log", source),
             off = util::metadata_numbers(meta, "offset", source);
  for (const auto* v : {&lo, &hi, &n, &lg, &off})
    if (v->size() != t.free.size())
      throw InputError(source + ": lo, hi, nodes, log and offset need one value per free parameter (" +
                       std::to_string(t.free.size()) + ")");
  std::size_t total = 1;
  for (std::size_t k = 0; k < t.free.size(); ++k) {
    if (!(n[k] >= 1 && n[k] <= 64 && n[k] == std::floor(n[k])) || !(lo[k] <= hi[k]))
      throw InputError(source + ": free parameter " + std::string(key(t.free[k])) + ": nodes must be a whole number 1-64 and lo <= hi");
    if (!(lg[k] == 0 || lg[k] == 1) || !(off[k] >= 0) || (lg[k] == 1 && !(lo[k] + off[k] > 0)))
      throw InputError(source + ": free parameter " + std::string(key(t.free[k])) +
                       ": log must be 0 or 1 and offset >= 0, with lo + offset > 0 where log is 1");
    t.bounds.push_back({lo[k], hi[k]});
    t.nodes.push_back(static_cast<int>(n[k]));
    t.log.push_back(lg[k] == 1);
    t.offset.push_back(off[k]);
    total *= static_cast<std::size_t>(n[k]);
  }
  for (const physics::ParameterInfo& row : physics::parameter_table())
    if (std::find_if(t.free.begin(), t.free.end(), [&](Parameter p) { return &p.info() == &row; }) == t.free.end())
      t.fixed.*(row.member) = util::metadata_number(meta, "fixed." + std::string(row.key), source);
  const util::Table tab = util::parse_csv(text, source);
  if (tab.rows() != total)
    throw InputError(source + ": " + std::to_string(tab.rows()) + " rows; the nodes need " + std::to_string(total));
  const auto &L = tab.data[tab.column("L")], &a = tab.data[tab.column("a")], &b = tab.data[tab.column("b")];
  t.lab.resize(total);
  for (std::size_t e = 0; e < total; ++e) t.lab[e] = {L[e], a[e], b[e]};
  return t;
}

void use_fit_model(ColorFitOptions& o, FitModel model) {
  o.fit_model = model;
  o.free = model == FitModel::extended
               ? extended_model_free(false)
               : std::vector<Parameter>{Parameter::melanin, Parameter::melanin_blend, Parameter::hemoglobin};
}

// ---------------------------------------------------------------------------------------------
// TextureFitter: dense table in transformed coordinates, trilinear interpolation.

namespace {
// Axis transforms: R_d responds to C_m and C_h roughly logarithmically, so their nodes are
// uniform in log(C + c0) (c0 keeps 0 reachable); beta_m is linear.
struct Axis {
  double lo = 0, hi = 0, c0 = 0;
  bool log = false;
  int n = 1;
  int order = 4;  // the extended table's piecewise-polynomial interpolation: nodes per stencil
  double t(double v) const { return log ? std::log(v + c0) : v; }
  double inv(double t) const { return log ? std::exp(t) - c0 : t; }
  double value(double u) const {  // u in [0, n - 1]
    if (n == 1) return lo;
    return inv(t(lo) + (t(hi) - t(lo)) * u / (n - 1));
  }
  double index(double v) const {
    if (n == 1) return 0;
    return (t(v) - t(lo)) / (t(hi) - t(lo)) * (n - 1);
  }
  // d value / d u at u.
  double slope(double u) const {
    if (n == 1) return 0;
    const double dt = (t(hi) - t(lo)) / (n - 1);
    return log ? (value(u) + c0) * dt : dt;
  }
};
// CIEDE2000's three components by CIELAB at l (central differences).
Eigen::Matrix3d delta_e_2000_jacobian(const color::Lab& target, const Eigen::Vector3d& l) {
  Eigen::Matrix3d D;
  for (int c = 0; c < 3; ++c) {
    Eigen::Vector3d lp = l, lm = l;
    lp[c] += 1e-4, lm[c] -= 1e-4;
    const auto a = color::delta_e_2000_components(target, {lp[0], lp[1], lp[2]});
    const auto b = color::delta_e_2000_components(target, {lm[0], lm[1], lm[2]});
    for (int q = 0; q < 3; ++q) D(q, c) = (a[q] - b[q]) / 2e-4;
  }
  return D;
}
}  // namespace

// The extended table's vectors and matrices: at most 16 free parameters and their prior rows,
// on the stack (no allocation in the per-colour solves).
using XVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 16, 1>;
using XMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 24, 16>;
using XJac = Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 16>;

struct TextureFitter::Impl {
  ColorFitter exact;
  Axis axis[3];  // melanin, melanin_blend, hemoglobin
  mutable std::once_flag once;
  mutable std::vector<Eigen::Vector3d> lab;  // [i_m][i_b][i_h], Lab

  // Extended model: one axis per free parameter, multilinear (table `xlab`, strides `xstride`).
  bool ext = false;
  std::vector<Parameter> xfree;
  std::vector<Axis> xaxis;
  std::vector<std::size_t> xstride;
  // The table's colours as single-precision vectors (1.8 MB for 147 456 nodes, which the
  // interpolations read from a core's 2 MB cache; 1e-5 of a CIELAB unit, far below their error).
  mutable std::vector<Eigen::Vector3f> xlab;
  mutable ColorTable table;  // either model's (the paper model's also as `lab`)
  bool allow_built_in = true;
  mutable bool built_in = false;

  Impl(ColorFitOptions o, bool built_in_table) : exact(std::move(o)), allow_built_in(built_in_table) {
    const auto& opt = exact.options();
    if (opt.fit_model == FitModel::extended) {
      init_extended();
      return;
    }
    const Parameter ps[3] = {Parameter::melanin, Parameter::melanin_blend, Parameter::hemoglobin};
    // 40 x 6 x 40 nodes: interpolation error well below 1 dE2000 (tests/fit).
    const int counts[3] = {40, 6, 40};
    const double c0[3] = {1e-3, 0, 5e-4};
    for (int k = 0; k < 3; ++k) {
      const bool free = std::find(opt.free.begin(), opt.free.end(), ps[k]) != opt.free.end();
      const Bounds b = exact.impl_->bounds_of(ps[k]);
      Axis& a = axis[k];
      if (!free) {
        a.lo = a.hi = get(opt.start, ps[k]);
        a.n = 1;
      } else {
        a.lo = b.lo;
        a.hi = b.hi;
        a.n = counts[k];
        a.c0 = c0[k];
        a.log = k != 1;
      }
    }
  }
  // The table's colours: R_d at every 10 nm (31 model evaluations instead of the grid's 151:
  // the adding-doubling solver costs ~35 us each), linearly interpolated to the colour grid and
  // weighted as `skin color` does. Skin R_d is smooth on that scale (the narrowest features, the
  // hemoglobin Q bands, are ~20 nm wide); the test bounds the colour error against the exact
  // model (TextureFit.TableInterpolationMatchesExactModel).
  color::Lab coarse_lab(const SkinParameters& p) const {
    const auto& im = *exact.impl_;
    const double step = 10.0;
    const double lo = im.lambda.front(), hi = im.lambda.back();
    std::vector<double> nodes, R;
    for (double l = lo; l < hi + 1e-9; l += step) nodes.push_back(l);
    if (nodes.back() < hi - 1e-9) nodes.push_back(hi);
    for (double l : nodes) R.push_back(im.model(p, l));
    const auto& w = im.cm.srgb_weights();
    color::Rgb c;
    std::size_t k = 0;
    for (std::size_t i = 0; i < im.lambda.size(); ++i) {
      const double l = im.lambda[i];
      while (k + 2 < nodes.size() && nodes[k + 1] < l) ++k;
      const double t = nodes.size() > 1 ? std::clamp((l - nodes[k]) / (nodes[k + 1] - nodes[k]), 0.0, 1.0) : 0.0;
      const double v = nodes.size() > 1 ? R[k] + t * (R[k + 1] - R[k]) : R[0];
      c.r += w[i][0] * v;
      c.g += w[i][1] * v;
      c.b += w[i][2] * v;
    }
    return im.lab_of(c);
  }
  std::size_t idx(int i, int j, int k) const {
    return (static_cast<std::size_t>(i) * static_cast<std::size_t>(axis[1].n) + static_cast<std::size_t>(j)) *
               static_cast<std::size_t>(axis[2].n) + static_cast<std::size_t>(k);
  }
  // Nodes per free parameter of the extended table: melanin and blood span 3 and 1.5 decades,
  // the epidermis' thickness acts together with melanin (its absorbance is their product), the
  // others span a factor 2-4 or are a weak lever (oxygenation). With these, the table's
  // piecewise-polynomial interpolation (xcubic: cubic, quadratic on the scattering axes) is the
  // model's colour to 0.0095 dE2000 (median over 200 random sets of the seven default free
  // parameters inside their ranges), worst 0.175 (ExtendedTexture.CubicTableIsTheModelsColour;
  // with six free parameters, before the dermis' scattering was one: 0.0056 median, 0.32 worst;
  // the multilinear one: 0.25 median, 1.7 at the 99th percentile).
  static int extended_nodes(Parameter p) {
    if (p == Parameter::melanin) return 16;
    if (p == Parameter::hemoglobin) return 8;
    if (p == Parameter::epidermis_thickness) return 6;
    if (p == Parameter::oxygenation) return 3;
    return 4;
  }
  // Nodes per interpolation stencil: four (cubic), but three (quadratic) for the two scattering
  // factors, whose colour is nearly quadratic in log(value) over the range: median 0.0095
  // dE2000 off the model instead of 0.0055, worst 0.175 instead of 0.183, with 6 912 nodes per
  // evaluation instead of 12 288 (CubicTableIsTheModelsColour; linear there: median 0.069).
  static int extended_order(Parameter p) {
    return p == Parameter::dermis_scattering_scale || p == Parameter::scattering_scale ? 3 : 4;
  }
  static constexpr std::size_t kMaxExtendedNodes = 200000;
  void init_extended() {
    ext = true;
    const auto& opt = exact.options();
    xfree = opt.free;
    if (xfree.size() > 16) throw InputError("free parameters: at most 16 for a texture");
    std::size_t total = 1;
    for (Parameter p : xfree) {
      const Bounds b = exact.impl_->bounds_of(p);
      Axis a;
      a.lo = b.lo;
      a.hi = b.hi;
      a.n = extended_nodes(p);
      a.order = extended_order(p);
      a.log = p.info().prior_log;
      a.c0 = a.log && b.lo <= 0 ? 1e-3 * (b.hi - b.lo) : 0.0;
      xaxis.push_back(a);
      total *= static_cast<std::size_t>(a.n);
    }
    if (total > kMaxExtendedNodes)
      throw InputError("free parameters: " + std::to_string(xfree.size()) + " free parameters need a texture table of " +
                       std::to_string(total) + " nodes; at most " + std::to_string(kMaxExtendedNodes) +
                       " (free fewer parameters for textures)");
    xstride.assign(xfree.size(), 1);
    for (std::size_t k = xfree.size(); k-- > 1;) xstride[k - 1] = xstride[k] * static_cast<std::size_t>(xaxis[k].n);
    // A prior term is affine in the index coordinate where the axis and the prior share their
    // scale (log or linear, nothing added): a + b u, no logarithm in the solves.
    xprior_a.assign(xfree.size(), 0.0);
    xprior_b.assign(xfree.size(), 0.0);
    xprior_affine.assign(xfree.size(), false);
    xprior_k.clear();
    for (std::size_t k = 0; k < xfree.size(); ++k) {
      const Parameter p = xfree[k];
      const Axis& a = xaxis[k];
      if (has_prior_centre(p)) xprior_k.push_back(static_cast<Eigen::Index>(k));
      if (!has_prior_centre(p) || a.n < 2) continue;
      const auto r = [&](double u) {
        return kColorPriorWeight * (prior_coordinate(p, a.value(u)) - prior_coordinate(p, p.info().prior_centre));
      };
      const double r0 = r(0), r1 = r(a.n - 1), rm = r(0.5 * (a.n - 1));
      xprior_a[k] = r0;
      xprior_b[k] = (r1 - r0) / (a.n - 1);
      xprior_affine[k] = a.c0 == 0 && a.log == p.info().prior_log && std::abs(rm - 0.5 * (r0 + r1)) <= 1e-12 * (1 + std::abs(r0) + std::abs(r1));
    }
  }
  std::vector<double> xprior_a, xprior_b;
  std::vector<bool> xprior_affine;
  std::vector<Eigen::Index> xprior_k;  // the free parameters with a prior term, in order
  SkinParameters xparams(const XVec& u) const {
    SkinParameters p = exact.options().start;
    for (std::size_t k = 0; k < xfree.size(); ++k) set(p, xfree[k], xaxis[k].value(u[static_cast<Eigen::Index>(k)]));
    return p;
  }
  // The node at flat index e, as index coordinates.
  XVec xnode(std::size_t e) const {
    XVec u(static_cast<Eigen::Index>(xfree.size()));
    for (std::size_t k = 0; k < xfree.size(); ++k)
      u[static_cast<Eigen::Index>(k)] = static_cast<double>((e / xstride[k]) % static_cast<std::size_t>(xaxis[k].n));
    return u;
  }
  std::size_t xtotal() const { return xstride.empty() ? 1 : xstride[0] * static_cast<std::size_t>(xaxis[0].n); }
  // The built-in table `name`, where it is the one these options need: the same free
  // parameters, nodes, spacing, bounds, fixed values and colour grid, and five of its nodes (both
  // ends, three inside) computed again by this fitter's model agree to 1e-6 (another transport
  // model, or a changed one, differs far more). node(e): the parameters at flat node index e.
  template <class Node>
  bool read_built_in(std::string_view name, const std::vector<Parameter>& free, const std::vector<Axis>& axes,
                     const Node& node) const {
    if (!(exact.options().grid == physics::WavelengthGrid())) return false;
    // (Its free parameters first, from the header: another set skips parsing its rows.)
    const auto meta = util::csv_metadata(util::data::embedded(name));
    if (const auto it = meta.find("free"); it == meta.end() || parse_parameter_list(it->second) != free) return false;
    ColorTable t = ColorTable::parse(util::data::embedded(name), std::string(name));
    if (t.free != free) return false;
    for (std::size_t k = 0; k < free.size(); ++k)
      if (t.nodes[k] != axes[k].n || t.bounds[k].lo != axes[k].lo || t.bounds[k].hi != axes[k].hi ||
          t.log[k] != axes[k].log || t.offset[k] != axes[k].c0)
        return false;
    SkinParameters fixed = exact.options().start;
    for (Parameter p : free) set(fixed, p, get(t.fixed, p));
    if (!(fixed == t.fixed)) return false;
    const std::size_t total = t.lab.size();
    for (std::size_t e : {std::size_t(0), total - 1, total / 3, total / 2, (2 * total) / 3 + 7}) {
      const color::Lab l = coarse_lab(node(e % total));
      const color::Lab& b = t.lab[e % total];
      if (!(std::abs(l.L - b.L) < 1e-6 && std::abs(l.a - b.a) < 1e-6 && std::abs(l.b - b.b) < 1e-6)) return false;
    }
    table = std::move(t);
    return true;
  }
  // An empty table over these free parameters and axes (its colours to be computed).
  ColorTable table_frame(const std::vector<Parameter>& free, const std::vector<Axis>& axes) const {
    ColorTable t;
    t.free = free;
    t.fixed = exact.options().start;
    std::size_t total = 1;
    for (const Axis& a : axes) {
      t.bounds.push_back({a.lo, a.hi});
      t.nodes.push_back(a.n);
      t.log.push_back(a.log);
      t.offset.push_back(a.c0);
      total *= static_cast<std::size_t>(a.n);
    }
    t.lab.resize(total);
    return t;
  }
  // Computes every node's colour, in batches, progress reported between them from this thread.
  template <class Node>
  void compute_table(const Node& node, const ProgressCallback& progress) const {
    const std::size_t total = table.lab.size();
    for (std::size_t start = 0; start < total; start += 2048) {
      const std::size_t end = std::min(total, start + 2048);
      tbb::parallel_for(start, end, [&](std::size_t e) {
        if (util::cancel::requested()) return;  // thrown below (out of call_once: built again next time)
        table.lab[e] = coarse_lab(node(e));
      });
      util::cancel::check();
      if (progress) progress(end, total);
    }
  }
  static constexpr std::string_view kPaperTable = "paper_color_table.csv";
  static constexpr std::string_view kExtendedTable = "extended_color_table.csv";
  void build_extended(const ProgressCallback& progress) const {
    const auto node = [this](std::size_t e) { return xparams(xnode(e)); };
    built_in = allow_built_in && read_built_in(kExtendedTable, xfree, xaxis, node);
    if (!built_in) {
      table = table_frame(xfree, xaxis);
      compute_table(node, progress);
    }
    xlab.resize(table.lab.size());
    for (std::size_t e = 0; e < xlab.size(); ++e)
      xlab[e] = Eigen::Vector3d(table.lab[e].L, table.lab[e].a, table.lab[e].b).cast<float>();
    // The starts: every other node on the axes with six or more (the start only needs the
    // right basin), in arrays of their own, each with its prior terms' sum of squares.
    xstart_L.clear(), xstart_a.clear(), xstart_b.clear(), xstart_prior.clear(), xstart_node.clear();
    for (std::size_t e = 0; e < xlab.size(); ++e) {
      bool on = true;
      for (std::size_t k = 0; k < xfree.size() && on; ++k)
        on = xaxis[k].n < 6 || ((e / xstride[k]) % static_cast<std::size_t>(xaxis[k].n)) % 2 == 0;
      if (!on) continue;
      const XVec u = xnode(e);
      double prior = 0;
      for (std::size_t k = 0; k < xfree.size(); ++k)
        if (has_prior_centre(xfree[k])) prior += std::pow(prior_residual(u, k), 2);
      xstart_L.push_back(xlab[e][0]), xstart_a.push_back(xlab[e][1]), xstart_b.push_back(xlab[e][2]);
      xstart_prior.push_back(prior);
      xstart_node.push_back(e);
    }
    // Sorted by L* (then by node, the scan's order), those the model cannot evaluate left out:
    // the search for the best start scans outward from the target's L* and stops where the
    // lightness difference alone exceeds the best cost (the other terms are >= 0), the same
    // start as a scan of all of them (18 432 with seven free parameters) in a few hundred. (The
    // plain scan made the 4096 x 4096 Lee Perry-Smith fit 10 % slower: paired runs, 2026-12-07.)
    xstart_fallback = xstart_node.empty() ? 0 : xstart_node.front();
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < xstart_L.size(); ++i)
      if (std::isfinite(xstart_L[i]) && std::isfinite(xstart_a[i]) && std::isfinite(xstart_b[i])) order.push_back(i);
    std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) {
      return xstart_L[i] != xstart_L[j] ? xstart_L[i] < xstart_L[j] : xstart_node[i] < xstart_node[j];
    });
    const auto gather = [&](auto& v) {
      std::remove_reference_t<decltype(v)> out;
      for (std::size_t i : order) out.push_back(v[i]);
      v = std::move(out);
    };
    gather(xstart_L), gather(xstart_a), gather(xstart_b), gather(xstart_prior), gather(xstart_node);
  }
  // The best start for a target (L, a, b) (the table's colour already shifted): the node of least
  // squared CIELAB distance plus prior terms, the lowest node on a tie.
  std::size_t best_start(double tL, double ta, double tb) const {
    const std::size_t N = xstart_L.size();
    if (N == 0) return xstart_fallback;
    double best = std::numeric_limits<double>::infinity();
    std::size_t at = N;
    const auto consider = [&](std::size_t i) {
      const double dL = xstart_L[i] - tL, da = xstart_a[i] - ta, db = xstart_b[i] - tb;
      const double c = dL * dL + da * da + db * db + xstart_prior[i];
      if (c < best || (c == best && at < N && xstart_node[i] < xstart_node[at])) best = c, at = i;
    };
    const std::size_t mid = static_cast<std::size_t>(std::lower_bound(xstart_L.begin(), xstart_L.end(), tL) - xstart_L.begin());
    std::size_t up = mid, down = mid;
    bool go_up = up < N, go_down = down > 0;
    while (go_up || go_down) {
      if (go_up) {
        const double dL = xstart_L[up] - tL;
        if (dL * dL > best) go_up = false;
        else if (consider(up), ++up == N) go_up = false;
      }
      if (go_down) {
        const double dL = xstart_L[down - 1] - tL;
        if (dL * dL > best) go_down = false;
        else if (consider(down - 1), --down == 0) go_down = false;
      }
    }
    return at < N ? xstart_node[at] : xstart_fallback;
  }
  mutable std::size_t xstart_fallback = 0;
  mutable std::vector<double> xstart_L, xstart_a, xstart_b, xstart_prior;
  mutable std::vector<std::size_t> xstart_node;
  // The prior term of free parameter k (which has a prior centre) at index coordinates u.
  double prior_residual(const XVec& u, std::size_t k) const {
    if (xprior_affine[k]) return xprior_a[k] + xprior_b[k] * u[static_cast<Eigen::Index>(k)];
    const Parameter p = xfree[k];
    return kColorPriorWeight * (prior_coordinate(p, xaxis[k].value(u[static_cast<Eigen::Index>(k)])) -
                                prior_coordinate(p, p.info().prior_centre));
  }
  // Piecewise-cubic interpolation of the table at index coordinates u: per axis Lagrange
  // polynomials through the four nearest nodes (three on a three-node axis, two on two), their
  // tensor product. Exactly the node's colour at a node.
  struct CubicWeights {
    std::array<std::size_t, 16> first{}, order{};
    std::array<std::array<double, 4>, 16> w{};
  };
  Eigen::Vector3d xcubic(const XVec& u) const {
    CubicWeights c;
    for (std::size_t k = 0; k < xfree.size(); ++k) {
      const int N = xaxis[k].n;
      const int m = std::min(N, xaxis[k].order);
      c.order[k] = static_cast<std::size_t>(m);
      if (N == 1) {
        c.w[k][0] = 1;
        continue;
      }
      const double x = std::clamp(u[static_cast<Eigen::Index>(k)], 0.0, static_cast<double>(N - 1));
      int i = m == 4 ? static_cast<int>(std::floor(x)) - 1 : (m == 3 ? static_cast<int>(std::lround(x)) - 1 : static_cast<int>(std::floor(x)));
      i = std::clamp(i, 0, N - m);
      c.first[k] = static_cast<std::size_t>(i);
      const double t = x - i;
      for (int j = 0; j < m; ++j) {
        double wj = 1;
        for (int q = 0; q < m; ++q)
          if (q != j) wj *= (t - q) / static_cast<double>(j - q);
        c.w[k][static_cast<std::size_t>(j)] = wj;
      }
    }
    if (xfree.empty()) return xlab[0].cast<double>();
    // The last two axes' stencil (the last one's alone on a one-axis table) multiplied out once:
    // up to 16 (offset, weight) pairs read at every point of the other axes' stencils.
    const std::size_t n = xfree.size(), inner_k = n >= 2 ? n - 2 : n - 1;
    Block b;
    if (n >= 2) {
      for (std::size_t i = 0; i < c.order[n - 2]; ++i)
        for (std::size_t j = 0; j < c.order[n - 1]; ++j) {
          b.offset[b.size] = (c.first[n - 2] + i) * xstride[n - 2] + (c.first[n - 1] + j) * xstride[n - 1];
          b.weight[b.size++] = c.w[n - 2][i] * c.w[n - 1][j];
        }
    } else {
      for (std::size_t j = 0; j < c.order[0]; ++j) b.offset[b.size] = c.first[0] + j, b.weight[b.size++] = c.w[0][j];
    }
    return xcubic_sum(0, inner_k, 0, c, b);
  }
  struct Block {
    std::array<std::size_t, 16> offset{};
    std::array<double, 16> weight{};
    std::size_t size = 0;
  };
  // The tensor product, one axis at a time down to the block of the last axes (each node read
  // once, one multiply-add per node).
  Eigen::Vector3d xcubic_sum(std::size_t k, std::size_t inner_k, std::size_t base, const CubicWeights& c, const Block& b) const {
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    if (k == inner_k) {
      for (std::size_t j = 0; j < b.size; ++j) v += b.weight[j] * xlab[base + b.offset[j]].cast<double>();
      return v;
    }
    for (std::size_t j = 0; j < c.order[k]; ++j)
      v += c.w[k][j] * xcubic_sum(k + 1, inner_k, base + (c.first[k] + j) * xstride[k], c, b);
    return v;
  }
  // Multilinear interpolation at index coordinates u, with the derivative per coordinate (J: 3 x n).
  Eigen::Vector3d xeval(const XVec& u, XJac* J) const {
    const std::size_t n = xfree.size();
    Lin c;
    for (std::size_t k = 0; k < n; ++k) {
      const int top = xaxis[k].n - 2;
      const int i = std::clamp(static_cast<int>(std::floor(u[static_cast<Eigen::Index>(k)])), 0, std::max(top, 0));
      c.i0[k] = static_cast<std::size_t>(i);
      c.f[k] = xaxis[k].n > 1 ? u[static_cast<Eigen::Index>(k)] - i : 0.0;
    }
    Eigen::Vector3d v;
    std::array<Eigen::Vector3d, 16> g;
    xlin(0, 0, c, v, g.data());
    if (J) {
      J->resize(3, static_cast<Eigen::Index>(n));
      for (std::size_t k = 0; k < n; ++k) J->col(static_cast<Eigen::Index>(k)) = g[k];
    }
    return v;
  }
  struct Lin {
    std::array<std::size_t, 16> i0{};
    std::array<double, 16> f{};
  };
  // Axes k..n-1 contracted at flat offset `base`: the value and its derivatives g[k..n-1] (one
  // axis at a time: each corner read once, each derivative blended on the way up).
  void xlin(std::size_t k, std::size_t base, const Lin& c, Eigen::Vector3d& v, Eigen::Vector3d* g) const {
    const std::size_t n = xfree.size();
    if (k == n) {
      v = xlab[base].cast<double>();
      return;
    }
    if (xaxis[k].n == 1) {  // a one-node axis: its only node, no derivative
      xlin(k + 1, base, c, v, g);
      g[k].setZero();
      return;
    }
    const std::size_t at = base + c.i0[k] * xstride[k];
    if (k + 1 == n) {  // the last axis: its two nodes directly
      const Eigen::Vector3d a = xlab[at].cast<double>();
      const Eigen::Vector3d b = xlab[at + xstride[k]].cast<double>();
      v = a + c.f[k] * (b - a);
      g[k] = b - a;
      return;
    }
    Eigen::Vector3d va, vb;
    std::array<Eigen::Vector3d, 16> gb;
    xlin(k + 1, at, c, va, g);
    xlin(k + 1, at + xstride[k], c, vb, gb.data());
    const double f = c.f[k];
    v = va + f * (vb - va);
    for (std::size_t j = k + 1; j < n; ++j) g[j] += f * (gb[j] - g[j]);
    g[k] = vb - va;
  }
  // The extended objective on the table: CIEDE2000 components between the target and the
  // table's colour plus `shift` (the exact model's correction), and the prior terms; LM over the
  // index coordinates, started at the best node (or at `start`).
  struct XSolved {
    XVec u;
    Eigen::Vector3d lab;  // table colour + shift
    int iterations = 0;
  };
  // Converged when no coordinate moved more than this (index units: a thousandth of a node
  // spacing, 0.05 % of melanin's value). On the Lee Perry-Smith albedo at 4096 x 4096 the mean
  // error moved by 5e-5 dE2000 from 1e-6, the share within 1 dE2000 by 2e-7, for 16 % less time.
  static constexpr double kXStepTolerance = 1e-3;
  XSolved xsolve(const color::Lab& target, const Eigen::Vector3d& shift, const XVec* start = nullptr) const {
    const auto n = static_cast<Eigen::Index>(xfree.size());
    const std::vector<Eigen::Index>& prior_k = xprior_k;
    const auto m = 3 + static_cast<Eigen::Index>(prior_k.size());
    auto prior_r = [&](const XVec& u, std::size_t j) { return prior_residual(u, static_cast<std::size_t>(prior_k[j])); };
    auto residual = [&](const XVec& u, const Eigen::Vector3d& l, XVec& r) {
      const auto d = color::delta_e_2000_components(target, {l[0], l[1], l[2]});
      r.resize(m);
      r[0] = d[0], r[1] = d[1], r[2] = d[2];
      for (std::size_t j = 0; j < prior_k.size(); ++j) r[3 + static_cast<Eigen::Index>(j)] = prior_r(u, j);
    };
    // Start: the best node by CIELAB distance and the prior terms.
    const Eigen::Vector3d t(target.L, target.a, target.b);
    const XVec u0 = start ? *start : xnode(best_start(t[0] - shift[0], t[1] - shift[1], t[2] - shift[2]));
    XVec u = u0;
    XVec hi(n);
    for (Eigen::Index k = 0; k < n; ++k) hi[k] = xaxis[static_cast<std::size_t>(k)].n - 1;
    XJac JL(3, n);
    Eigen::Vector3d l = xeval(u, &JL) + shift;
    XVec r;
    residual(u, l, r);
    double cost = r.squaredNorm();
    double mu = 1e-3;
    int it = 0;
    bool converged = false;
    for (; it < 40 && !converged; ++it) {
      // Jacobian: CIEDE2000 components by CIELAB (forward differences from r) times the
      // table's; the prior rows exact where affine, else by central differences in u.
      XMat Jr = XMat::Zero(m, n);
      Eigen::Matrix3d D;
      for (int c = 0; c < 3; ++c) {
        Eigen::Vector3d lp = l;
        lp[c] += 1e-4;
        const auto a = color::delta_e_2000_components(target, {lp[0], lp[1], lp[2]});
        for (int q = 0; q < 3; ++q) D(q, c) = (a[q] - r[q]) / 1e-4;
      }
      Jr.topRows(3) = D * JL;
      for (std::size_t j = 0; j < prior_k.size(); ++j) {
        const Eigen::Index k = prior_k[j];
        if (xprior_affine[static_cast<std::size_t>(k)]) {
          Jr(3 + static_cast<Eigen::Index>(j), k) = xprior_b[static_cast<std::size_t>(k)];
          continue;
        }
        XVec up = u, um = u;
        up[k] += 1e-5, um[k] -= 1e-5;
        Jr(3 + static_cast<Eigen::Index>(j), k) = (prior_r(up, j) - prior_r(um, j)) / 2e-5;
      }
      XMat A = Jr.transpose() * Jr;
      XVec g = Jr.transpose() * r;
      // Parameters on a bound that the gradient pushes outward stay there this step (projected
      // LM: otherwise the clipped step leaves the descent direction and the solve crawls).
      for (Eigen::Index k = 0; k < n; ++k)
        if ((u[k] <= 0.0 && g[k] > 0) || (u[k] >= hi[k] && g[k] < 0)) {
          A.row(k).setZero();
          A.col(k).setZero();
          A(k, k) = 1;
          g[k] = 0;
        }
      bool accepted = false;
      for (int tries = 0; tries < 10 && !accepted; ++tries) {
        XMat M = A;
        for (Eigen::Index k = 0; k < n; ++k) M(k, k) += mu * std::max(A(k, k), 1e-9);
        const XVec step = M.ldlt().solve(-g);
        const XVec un = (u + step).cwiseMax(0.0).cwiseMin(hi);
        XJac Jn(3, n);
        const Eigen::Vector3d ln = xeval(un, &Jn) + shift;
        XVec rn;
        residual(un, ln, rn);
        const double cn = rn.squaredNorm();
        if (cn < cost) {
          const double moved = (un - u).cwiseAbs().maxCoeff();
          const bool flat = cost - cn <= 1e-10 * cost;  // no longer worth another step
          u = un, l = ln, JL = Jn, r = rn, cost = cn;
          mu = std::max(mu * 0.3, 1e-9);
          accepted = true;
          if (moved < kXStepTolerance || flat) converged = true;
        } else {
          mu *= 4;
        }
      }
      if (!accepted) break;
    }
    return {u, l, it};
  }
  // The multilinear table is ~0.25 dE2000 off the model (typically; 2 at worst), its cubic
  // interpolation ~0.006 (0.11 at the 99th percentile), but the cubic one is ~60x dearer to
  // evaluate with its derivatives. So each colour is solved twice on the multilinear table: the
  // second time with its colour shifted by the cubic minus the multilinear colour at the first
  // solution (the difference varies slowly near it); the colour reported is the cubic one at
  // the second solution. No model evaluation per colour.
  XSolved xsolve_refined(const color::Lab& target) const {
    const XSolved first = xsolve(target, Eigen::Vector3d::Zero());
    const Eigen::Vector3d shift = xreference(first.u) - first.lab;
    XSolved s = xsolve(target, shift, &first.u);
    s.lab = xreference(s.u);
    return s;
  }
  // The model's colour at u: the cubic interpolation, or where its stencil reaches a node the
  // model cannot evaluate (NaN: outside a solver's validated range, e.g. the multipole's thin
  // epidermis), the model itself.
  Eigen::Vector3d xreference(const XVec& u) const {
    const Eigen::Vector3d c = xcubic(u);
    if (c.allFinite()) return c;
    const color::Lab e = coarse_lab(xparams(u));
    return {e.L, e.a, e.b};
  }
  // One standard deviation per free parameter at the solution u of `target` (parameter units):
  // the residuals' Jacobian from the cubic table (central differences in u, one-sided at a
  // bound) and the prior rows, through standard_errors_scaled as the colour fit does.
  std::vector<double> xuncertainty(const color::Lab& target, const XVec& u) const {
    const auto n = static_cast<Eigen::Index>(xfree.size());
    const std::vector<Eigen::Index>& prior_k = xprior_k;
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(3 + static_cast<Eigen::Index>(prior_k.size()), n);
    Eigen::Matrix<double, 3, Eigen::Dynamic> Jc(3, n);
    constexpr double h = 1e-3;
    for (Eigen::Index k = 0; k < n; ++k) {
      const double top = xaxis[static_cast<std::size_t>(k)].n - 1;
      XVec up = u, um = u;
      up[k] = std::min(u[k] + h, top);
      um[k] = std::max(u[k] - h, 0.0);
      Jc.col(k) = (xreference(up) - xreference(um)) / (up[k] - um[k]);
    }
    J.topRows(3) = delta_e_2000_jacobian(target, xreference(u)) * Jc;
    for (std::size_t j = 0; j < prior_k.size(); ++j) {
      const auto k = static_cast<std::size_t>(prior_k[j]);
      XVec up = u, um = u;
      up[prior_k[j]] += 1e-5, um[prior_k[j]] -= 1e-5;
      J(3 + static_cast<Eigen::Index>(j), prior_k[j]) =
          xprior_affine[k] ? xprior_b[k] : (prior_residual(up, k) - prior_residual(um, k)) / 2e-5;
    }
    const Eigen::VectorXd se = detail::standard_errors_scaled(J, 1.0);
    std::vector<double> sd(xfree.size());
    for (std::size_t k = 0; k < xfree.size(); ++k)
      sd[k] = se[static_cast<Eigen::Index>(k)] * std::abs(xaxis[k].slope(u[static_cast<Eigen::Index>(k)]));
    return sd;
  }
  // The paper model's: Lab residuals and the beta_m prior row, the trilinear table's derivatives;
  // for the free ones of (melanin, melanin_blend, hemoglobin), in that order.
  std::vector<double> uncertainty(const Eigen::Vector3d& u) const {
    const auto& opt = exact.options();
    Eigen::Matrix3d Jl;
    eval(u, &Jl);
    std::vector<int> free;
    for (int k = 0; k < 3; ++k)
      if (axis[k].n > 1) free.push_back(k);
    const bool reg = axis[1].n > 1;
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(3 + (reg ? 1 : 0), static_cast<Eigen::Index>(free.size()));
    for (std::size_t j = 0; j < free.size(); ++j) {
      const auto c = static_cast<Eigen::Index>(j);
      J.block(0, c, 3, 1) = Jl.col(free[j]);
      if (reg && free[j] == 1) J(3, c) = opt.melanin_blend_weight * (axis[1].hi - axis[1].lo) / (axis[1].n - 1);
    }
    const Eigen::VectorXd se = detail::standard_errors_scaled(J, 1.0);
    std::vector<double> sd;
    for (std::size_t j = 0; j < free.size(); ++j)
      sd.push_back(se[static_cast<Eigen::Index>(j)] * std::abs(axis[free[j]].slope(u[free[j]])));
    return sd;
  }
  unsigned bound_bits_x(const XVec& u) const {
    unsigned bits = 0;
    for (std::size_t k = 0; k < xfree.size(); ++k)
      if (xaxis[k].n > 1 && (u[static_cast<Eigen::Index>(k)] <= 1e-9 || u[static_cast<Eigen::Index>(k)] >= xaxis[k].n - 1 - 1e-9))
        bits |= 1u << k;
    return bits;
  }
  void build(const ProgressCallback& progress) const {
    if (ext) {
      build_extended(progress);
      return;
    }
    static const std::vector<Parameter> kFree = {Parameter::melanin, Parameter::melanin_blend, Parameter::hemoglobin};
    const std::vector<Axis> axes(std::begin(axis), std::end(axis));
    const auto node = [this](std::size_t e) {
      const int k = static_cast<int>(e % axis[2].n);
      const int j = static_cast<int>((e / axis[2].n) % axis[1].n);
      const int i = static_cast<int>(e / (static_cast<std::size_t>(axis[2].n) * axis[1].n));
      SkinParameters p = exact.options().start;
      p.melanin = axis[0].value(i);
      p.melanin_blend = axis[1].value(j);
      p.hemoglobin = axis[2].value(k);
      return p;
    };
    built_in = allow_built_in && read_built_in(kPaperTable, kFree, axes, node);
    if (!built_in) {
      table = table_frame(kFree, axes);
      compute_table(node, progress);
    }
    lab.resize(table.lab.size());
    for (std::size_t e = 0; e < lab.size(); ++e) lab[e] = {table.lab[e].L, table.lab[e].a, table.lab[e].b};
  }
  // Trilinear interpolation at index coordinates u, with the derivative per coordinate.
  Eigen::Vector3d eval(const Eigen::Vector3d& u, Eigen::Matrix3d* J) const {
    int i0[3];
    double f[3];
    for (int k = 0; k < 3; ++k) {
      if (axis[k].n == 1) {
        i0[k] = 0;
        f[k] = 0;
        continue;
      }
      i0[k] = std::clamp(static_cast<int>(std::floor(u[k])), 0, axis[k].n - 2);
      f[k] = u[k] - i0[k];
    }
    const int s1 = axis[1].n > 1 ? 1 : 0, s0 = axis[0].n > 1 ? 1 : 0, s2 = axis[2].n > 1 ? 1 : 0;
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    if (J) J->setZero();
    for (int a = 0; a <= s0; ++a)
      for (int b = 0; b <= s1; ++b)
        for (int c = 0; c <= s2; ++c) {
          const double wa = s0 ? (a ? f[0] : 1 - f[0]) : 1, wb = s1 ? (b ? f[1] : 1 - f[1]) : 1,
                       wc = s2 ? (c ? f[2] : 1 - f[2]) : 1;
          const Eigen::Vector3d& node = lab[idx(i0[0] + a, i0[1] + b, i0[2] + c)];
          v += wa * wb * wc * node;
          if (J) {
            if (s0) J->col(0) += (a ? 1.0 : -1.0) * wb * wc * node;
            if (s1) J->col(1) += (b ? 1.0 : -1.0) * wa * wc * node;
            if (s2) J->col(2) += (c ? 1.0 : -1.0) * wa * wb * node;
          }
        }
    return v;
  }
  // Bit k: parameter k (melanin, melanin_blend, hemoglobin) ended on its search bound.
  unsigned char bound_bits(const Eigen::Vector3d& u) const {
    unsigned char bits = 0;
    for (int k = 0; k < 3; ++k)
      if (axis[k].n > 1 && (u[k] <= 1e-9 || u[k] >= axis[k].n - 1 - 1e-9)) bits |= static_cast<unsigned char>(1u << k);
    return bits;
  }
  SkinParameters params(const Eigen::Vector3d& u) const {
    SkinParameters p = exact.options().start;
    p.melanin = axis[0].value(u[0]);
    p.melanin_blend = axis[1].value(u[1]);
    p.hemoglobin = axis[2].value(u[2]);
    return p;
  }

  // The per-pixel objective on the table: a small LM with fixed-size matrices.
  struct Solved {
    Eigen::Vector3d u;
    Eigen::Vector3d lab;
    int iterations;
  };
  Solved solve(const Eigen::Vector3d& target) const {
    const auto& opt = exact.options();
    const double w = axis[1].n > 1 ? opt.melanin_blend_weight : 0.0;
    const double prior_u = axis[1].index(opt.melanin_blend_prior);
    const double beta_per_u = axis[1].n > 1 ? (axis[1].hi - axis[1].lo) / (axis[1].n - 1) : 0.0;
    auto cost_of = [&](const Eigen::Vector3d& l, const Eigen::Vector3d& u) {
      const double reg = w * beta_per_u * (u[1] - prior_u);
      return (l - target).squaredNorm() + reg * reg;
    };
    // Start: the best node on a stride-2 sub-grid.
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i < axis[0].n; i += 2)
      for (int j = 0; j < axis[1].n; ++j)
        for (int k = 0; k < axis[2].n; k += 2) {
          const Eigen::Vector3d uu(i, j, k);
          const double c = cost_of(lab[idx(i, j, k)], uu);
          if (c < best) best = c, u = uu;
        }
    Eigen::Vector3d hi;
    for (int k = 0; k < 3; ++k) hi[k] = axis[k].n - 1;
    Eigen::Matrix3d J;
    Eigen::Vector3d l = eval(u, &J);
    double cost = cost_of(l, u);
    double mu = 1e-3;
    int it = 0;
    bool converged = false;
    for (; it < 40 && !converged; ++it) {
      // Residual (l - target, reg); Jacobian (J; w beta_per_u e_1).
      const Eigen::Vector3d r = l - target;
      const double reg = w * beta_per_u * (u[1] - prior_u), dreg = w * beta_per_u;
      Eigen::Matrix3d A = J.transpose() * J;
      Eigen::Vector3d g = J.transpose() * r;
      A(1, 1) += dreg * dreg;
      g[1] += dreg * reg;
      for (int k = 0; k < 3; ++k)
        if (axis[k].n == 1) A(k, k) = 1, g[k] = 0;
      bool accepted = false;
      for (int tries = 0; tries < 10 && !accepted; ++tries) {
        Eigen::Matrix3d M = A;
        for (int k = 0; k < 3; ++k) M(k, k) += mu * std::max(A(k, k), 1e-9);
        const Eigen::Vector3d step = M.ldlt().solve(-g);
        const Eigen::Vector3d un = (u + step).cwiseMax(0.0).cwiseMin(hi);
        Eigen::Matrix3d Jn;
        const Eigen::Vector3d ln = eval(un, &Jn);
        const double cn = cost_of(ln, un);
        if (cn < cost) {
          const double moved = (un - u).cwiseAbs().maxCoeff();
          u = un, l = ln, J = Jn, cost = cn;
          mu = std::max(mu * 0.3, 1e-9);
          accepted = true;
          if (moved < 1e-6) converged = true;
        } else {
          mu *= 4;
        }
      }
      if (!accepted) break;
    }
    return {u, l, it};
  }
};

TextureFitter::TextureFitter(ColorFitOptions options, bool built_in_table) {
  impl_ = std::make_unique<Impl>(std::move(options), built_in_table);
}
TextureFitter::~TextureFitter() = default;
TextureFitter::TextureFitter(TextureFitter&&) noexcept = default;
TextureFitter& TextureFitter::operator=(TextureFitter&&) noexcept = default;
void TextureFitter::prepare(const ProgressCallback& progress) const {
  std::call_once(impl_->once, [this, &progress] { impl_->build(progress); });
}

color::Lab TextureFitter::lab(const SkinParameters& p) const {
  prepare();
  if (impl_->ext) {
    XVec u(static_cast<Eigen::Index>(impl_->xfree.size()));
    for (std::size_t k = 0; k < impl_->xfree.size(); ++k)
      u[static_cast<Eigen::Index>(k)] = impl_->xaxis[k].index(get(p, impl_->xfree[k]));
    const Eigen::Vector3d l = impl_->xreference(u);
    return {l[0], l[1], l[2]};
  }
  const Eigen::Vector3d u(impl_->axis[0].index(p.melanin), impl_->axis[1].index(p.melanin_blend),
                          impl_->axis[2].index(p.hemoglobin));
  const Eigen::Vector3d l = impl_->eval(u, nullptr);
  return {l[0], l[1], l[2]};
}

color::Lab TextureFitter::node_lab(const SkinParameters& p) const { return impl_->coarse_lab(p); }

const ColorTable& TextureFitter::color_table() const {
  prepare();
  return impl_->table;
}

bool TextureFitter::uses_built_in_table() const {
  prepare();
  return impl_->built_in;
}

ColorFitResult TextureFitter::fit_color(const color::Rgb& rgb) const {
  prepare();
  const color::Lab t = impl_->exact.impl_->lab_of(rgb);
  if (impl_->ext) {
    const Impl& m = *impl_;
    const auto s = m.xsolve_refined(t);
    ColorFitResult r;
    r.parameters = m.xparams(s.u);
    r.target = t;
    r.fitted = {s.lab[0], s.lab[1], s.lab[2]};
    r.delta_e = color::delta_e_2000(r.target, r.fitted);
    r.iterations = s.iterations;
    r.fit_model = FitModel::extended;
    r.outside_gamut = r.delta_e > kGamutDeltaE;
    r.free = m.xfree;
    const unsigned bits = m.bound_bits_x(s.u);
    for (std::size_t k = 0; k < m.xfree.size(); ++k) r.at_bound.push_back(((bits >> k) & 1u) != 0);
    r.uncertainty = m.xuncertainty(t, s.u);
    return r;
  }
  const auto s = impl_->solve({t.L, t.a, t.b});
  ColorFitResult r;
  r.parameters = impl_->params(s.u);
  r.target = t;
  r.fitted = {s.lab[0], s.lab[1], s.lab[2]};
  r.delta_e = color::delta_e_2000(r.target, r.fitted);
  r.iterations = s.iterations;
  r.free.clear();
  const Parameter ps[3] = {Parameter::melanin, Parameter::melanin_blend, Parameter::hemoglobin};
  const unsigned char bits = impl_->bound_bits(s.u);
  for (int k = 0; k < 3; ++k)
    if (impl_->axis[k].n > 1) r.free.push_back(ps[k]), r.at_bound.push_back(((bits >> k) & 1u) != 0);
  r.uncertainty = impl_->uncertainty(s.u);
  return r;
}

ParameterMaps TextureFitter::fit(const Image& img, const ProgressCallback& progress, bool uncertainty) const {
  if (img.width <= 0 || img.height <= 0 || img.rgb.size() != static_cast<std::size_t>(img.width) * img.height * 3)
    throw InputError("texture: expected an RGB image, got " + std::to_string(img.width) + "x" +
                     std::to_string(img.height) + " with " + std::to_string(img.rgb.size()) + " values");
  // An albedo is a reflectance: every texel's linear channel finite and within [0, 1] (an EXR
  // may hold anything; NaN or 1.7 is a damaged or wrongly exposed texture, not a skin colour).
  for (std::size_t i = 0; i < img.rgb.size(); ++i)
    if (!(img.rgb[i] >= 0.0f && img.rgb[i] <= 1.0f)) {
      const std::size_t texel = i / 3;
      throw InputError("texture: texel (" + std::to_string(texel % static_cast<std::size_t>(img.width)) + ", " +
                       std::to_string(texel / static_cast<std::size_t>(img.width)) + ") channel " + "RGB"[i % 3] +
                       " = " + format_number(img.rgb[i]) + "; allowed: a linear albedo within [0, 1]");
    }
  prepare();
  const std::size_t npix = static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height);
  // Distinct colours (16 bits per linear channel: distinct 8- and 16-bit sRGB inputs stay
  // distinct), each solved once. An open-addressing hash of the 48-bit keys gives every texel the
  // index of its colour, in the order colours first appear (each colour's result does not depend
  // on that order); no sort of the texels, and 4 bytes per texel besides the distinct colours
  // (worst case, 8192 x 8192 texels all distinct: 1.6 GB for keys, table, indices and counts,
  // where the sort took 1.1 GB; a 4096 x 4096 albedo's 78 702 colours: 2 MB).
  auto key_of = [&img](std::size_t i) {
    std::uint64_t k = 0;
    for (int c = 0; c < 3; ++c) {
      const double v = std::clamp(static_cast<double>(img.rgb[i * 3 + static_cast<std::size_t>(c)]), 0.0, 1.0);
      k = (k << 16) | static_cast<std::uint64_t>(std::lround(v * 65535.0));
    }
    return k;
  };
  std::vector<std::uint32_t> slot(npix);
  std::vector<std::uint64_t> uniq;   // the distinct keys
  std::vector<std::uint32_t> count;  // texels per distinct key
  {
    // The table holds indices into `uniq` (4 bytes a slot, at most half full).
    constexpr std::uint32_t kEmpty = ~std::uint32_t(0);
    int bits = 12;
    std::vector<std::uint32_t> table(std::size_t(1) << bits, kEmpty);
    auto home = [&bits](std::uint64_t k) { return static_cast<std::size_t>((k * 0x9E3779B97F4A7C15ull) >> (64 - bits)); };
    auto find_or_insert = [&](std::uint64_t k) -> std::uint32_t {
      std::size_t mask = table.size() - 1, h = home(k);
      while (table[h] != kEmpty && uniq[table[h]] != k) h = (h + 1) & mask;
      if (table[h] != kEmpty) return table[h];
      const auto q = static_cast<std::uint32_t>(uniq.size());
      uniq.push_back(k);
      count.push_back(0);
      table[h] = q;
      if (2 * uniq.size() > table.size()) {  // grow to keep the load at most 1/2
        ++bits;
        table.assign(std::size_t(1) << bits, kEmpty);
        mask = table.size() - 1;
        for (std::uint32_t r = 0; r < uniq.size(); ++r) {
          std::size_t g = home(uniq[r]);
          while (table[g] != kEmpty) g = (g + 1) & mask;
          table[g] = r;
        }
      }
      return q;
    };
    std::uint64_t last_key = ~std::uint64_t(0);  // (keys use 48 bits)
    std::uint32_t last_slot = 0;
    for (std::size_t i = 0; i < npix; ++i) {
      const std::uint64_t k = key_of(i);
      if (k != last_key) last_key = k, last_slot = find_or_insert(k);
      slot[i] = last_slot;
      ++count[last_slot];
    }
  }
  if (impl_->ext) return fit_extended(img.width, img.height, slot, uniq, count, progress, uncertainty);
  struct Out {
    float m, b, h, e;
    unsigned char bound;  // bit k: parameter k (melanin, melanin_blend, hemoglobin) on its bound
  };
  std::vector<Out> solved(uniq.size());
  const Impl& m = *impl_;
  std::vector<Parameter> free;  // the free ones of the three, in that order
  for (int k = 0; k < 3; ++k)
    if (m.axis[k].n > 1) free.push_back(std::array{Parameter::melanin, Parameter::melanin_blend, Parameter::hemoglobin}[static_cast<std::size_t>(k)]);
  std::vector<float> sd(uncertainty ? uniq.size() * free.size() : 0);
  std::atomic<std::size_t> done{0};
  const std::size_t chunk = 256;
  const std::size_t nchunks = (uniq.size() + chunk - 1) / chunk;
  std::size_t next_chunk = 0;
  // Chunks of colours in parallel; progress reported between batches from this thread.
  while (next_chunk < nchunks) {
    const std::size_t batch_end = std::min(nchunks, next_chunk + 64);
    tbb::parallel_for(next_chunk, batch_end, [&](std::size_t ch) {
      for (std::size_t q = ch * chunk; q < std::min(uniq.size(), (ch + 1) * chunk); ++q) {
        if (util::cancel::requested()) return;  // thrown below, after the batch
        const std::uint64_t k = uniq[q];
        const auto channel = [k](int shift) { return static_cast<double>((k >> shift) & 0xffff) / 65535.0; };
        const color::Rgb rgb{channel(32), channel(16), channel(0)};
        const color::Lab t = m.exact.impl_->lab_of(rgb);
        const auto s = m.solve({t.L, t.a, t.b});
        const SkinParameters p = m.params(s.u);
        const double e = color::delta_e_2000(t, {s.lab[0], s.lab[1], s.lab[2]});
        const unsigned char bound = m.bound_bits(s.u);
        solved[q] = {static_cast<float>(p.melanin), static_cast<float>(p.melanin_blend),
                     static_cast<float>(p.hemoglobin), static_cast<float>(e), bound};
        if (uncertainty) {
          const std::vector<double> u = m.uncertainty(s.u);
          for (std::size_t j = 0; j < free.size(); ++j) sd[q * free.size() + j] = static_cast<float>(u[j]);
        }
      }
      done += chunk;
    });
    util::cancel::check();
    next_chunk = batch_end;
    if (progress) progress(std::min(done.load(), uniq.size()), uniq.size());
  }
  ParameterMaps maps;
  maps.width = img.width;
  maps.height = img.height;
  maps.melanin.resize(npix);
  maps.melanin_blend.resize(npix);
  maps.hemoglobin.resize(npix);
  maps.error.resize(npix);
  if (uncertainty) {
    maps.uncertainty_parameters = free;
    maps.uncertainty.assign(free.size(), std::vector<float>(npix));
  }
  tbb::parallel_for(std::size_t(0), npix, [&](std::size_t i) {
    const Out& r = solved[slot[i]];
    maps.melanin[i] = r.m;
    maps.melanin_blend[i] = r.b;
    maps.hemoglobin[i] = r.h;
    maps.error[i] = r.e;
    for (std::size_t k = 0; k < maps.uncertainty.size(); ++k) maps.uncertainty[k][i] = sd[slot[i] * free.size() + k];
  });
  maps.update_error_statistics();
  for (std::size_t q = 0; q < uniq.size(); ++q) {
    const unsigned char b = solved[q].bound;
    for (int k = 0; k < 3; ++k)
      if ((b >> k) & 1u) maps.at_bound[static_cast<std::size_t>(k)] += count[q];
    if (b != 0) maps.any_at_bound += count[q];
  }
  return maps;
}

ParameterMaps TextureFitter::fit_extended(int width, int height, const std::vector<std::uint32_t>& slot,
                                          const std::vector<std::uint64_t>& uniq,
                                          const std::vector<std::uint32_t>& count,
                                          const ProgressCallback& progress, bool uncertainty) const {
  const Impl& m = *impl_;
  const std::size_t nfree = m.xfree.size();
  // The distinct colours' CIELAB.
  std::vector<color::Lab> target(uniq.size());
  tbb::parallel_for(std::size_t(0), uniq.size(), [&](std::size_t q) {
    const std::uint64_t k = uniq[q];
    const auto channel = [k](int shift) { return static_cast<double>((k >> shift) & 0xffff) / 65535.0; };
    target[q] = m.exact.impl_->lab_of({channel(32), channel(16), channel(0)});
  });
  const std::size_t total = uniq.size();
  std::atomic<std::size_t> done{0};
  // Per distinct colour: its free parameters (nfree values, flat), error and bound bits.
  std::vector<float> value(uniq.size() * nfree), error(uniq.size());
  std::vector<float> sd(uncertainty ? uniq.size() * nfree : 0);
  std::vector<unsigned> bound(uniq.size());
  // Batches of colours in parallel; progress reported between batches from this thread.
  for (std::size_t start = 0; start < total; start += 4096) {
    const std::size_t end = std::min(total, start + 4096);
    tbb::parallel_for(start, end, [&](std::size_t q) {
      if (util::cancel::requested()) return;  // thrown below, after the batch
      const auto s = m.xsolve_refined(target[q]);
      for (std::size_t k = 0; k < nfree; ++k)
        value[q * nfree + k] = static_cast<float>(m.xaxis[k].value(s.u[static_cast<Eigen::Index>(k)]));
      error[q] = static_cast<float>(color::delta_e_2000(target[q], {s.lab[0], s.lab[1], s.lab[2]}));
      bound[q] = m.bound_bits_x(s.u);
      if (uncertainty) {
        const std::vector<double> u = m.xuncertainty(target[q], s.u);
        for (std::size_t k = 0; k < nfree; ++k) sd[q * nfree + k] = static_cast<float>(u[k]);
      }
      ++done;
    });
    util::cancel::check();
    if (progress) progress(done.load(), total);
  }
  ParameterMaps maps;
  maps.width = width;
  maps.height = height;
  const std::size_t npix = slot.size();
  const SkinParameters& fixed = m.exact.options().start;
  // Where each free parameter goes: the three named planes, else `more`.
  const Parameter named[3] = {Parameter::melanin, Parameter::melanin_blend, Parameter::hemoglobin};
  std::vector<std::vector<float>*> plane(nfree);
  std::vector<int> named_of(nfree, -1);
  std::vector<float>* planes3[3] = {&maps.melanin, &maps.melanin_blend, &maps.hemoglobin};
  for (int k = 0; k < 3; ++k) planes3[k]->assign(npix, static_cast<float>(get(fixed, named[k])));
  for (std::size_t k = 0; k < nfree; ++k)
    if (m.xfree[k] == named[0] || m.xfree[k] == named[1] || m.xfree[k] == named[2])
      named_of[k] = m.xfree[k] == named[0] ? 0 : (m.xfree[k] == named[1] ? 1 : 2);
  for (std::size_t k = 0; k < nfree; ++k)
    if (named_of[k] < 0) maps.more_parameters.push_back(m.xfree[k]);
  maps.more.assign(maps.more_parameters.size(), std::vector<float>(npix));
  maps.more_at_bound.assign(maps.more_parameters.size(), 0);
  for (std::size_t k = 0, j = 0; k < nfree; ++k) plane[k] = named_of[k] >= 0 ? planes3[named_of[k]] : &maps.more[j++];
  maps.error.resize(npix);
  // The uncertainty maps in the maps' order: the three named ones that are free, then `more`'s.
  std::vector<std::size_t> sd_of;  // the free parameter of each uncertainty map
  if (uncertainty) {
    for (int c = 0; c < 3; ++c)
      for (std::size_t k = 0; k < nfree; ++k)
        if (named_of[k] == c) sd_of.push_back(k);
    for (std::size_t k = 0; k < nfree; ++k)
      if (named_of[k] < 0) sd_of.push_back(k);
    for (std::size_t k : sd_of) maps.uncertainty_parameters.push_back(m.xfree[k]);
    maps.uncertainty.assign(nfree, std::vector<float>(npix));
  }
  tbb::parallel_for(std::size_t(0), npix, [&](std::size_t i) {
    const std::size_t q = slot[i];
    for (std::size_t k = 0; k < nfree; ++k) (*plane[k])[i] = value[q * nfree + k];
    maps.error[i] = error[q];
    for (std::size_t j = 0; j < sd_of.size(); ++j) maps.uncertainty[j][i] = sd[q * nfree + sd_of[j]];
  });
  maps.update_error_statistics();
  for (std::size_t q = 0; q < uniq.size(); ++q) {
    const unsigned b = bound[q];
    for (std::size_t k = 0, j = 0; k < nfree; ++k) {
      const bool on = ((b >> k) & 1u) != 0;
      if (named_of[k] >= 0) {
        if (on) maps.at_bound[static_cast<std::size_t>(named_of[k])] += count[q];
      } else {
        if (on) maps.more_at_bound[j] += count[q];
        ++j;
      }
    }
    if (b != 0) maps.any_at_bound += count[q];
  }
  return maps;
}

void ParameterMaps::update_error_statistics() {
  double sum = 0, mx = 0;
  std::size_t below = 0;
  for (float e : error) {
    sum += e;
    mx = std::max(mx, static_cast<double>(e));
    below += e < 1.0f;
  }
  const auto n = static_cast<double>(error.size());
  mean_error = error.empty() ? 0 : sum / n;
  double sum_out = 0;
  std::size_t out = 0;
  for (float e : error)
    if (e > kGamutDeltaE) sum_out += e, ++out;
  mean_error_outside = out ? sum_out / static_cast<double>(out) : 0.0;
  max_error = mx;
  fraction_below_1 = error.empty() ? 0 : static_cast<double>(below) / n;
}

}  // namespace skin::fit
