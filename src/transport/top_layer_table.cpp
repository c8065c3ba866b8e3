// Tabulated transport of a thin top layer (top_layer_table.hpp).
#include "skin/transport/top_layer_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <ostream>
#include <sstream>

#include "skin/util/charconv.hpp"
#include "skin/util/error.hpp"
#include "skin/util/interpolation.hpp"
#include "skin/util/table.hpp"

namespace skin::accurate {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

void accumulate(std::vector<double>& out, const std::vector<double>& a, double w) {
  if (out.empty()) out.assign(a.size(), 0.0);
  for (std::size_t i = 0; i < a.size(); ++i) out[i] += w * a[i];
}

}  // namespace

bool TopLayerTable::covers(double alpha_prime, double tau_prime) const {
  return std::isfinite(alpha_prime) && alpha_prime >= 0 && alpha_prime <= 1 &&
         tau_prime >= tau.front() && tau_prime <= tau.back();
}

TopLayerTable::Sample TopLayerTable::sample(double alpha_prime, double tau_prime) const {
  const double xv = std::sqrt(std::max(0.0, 1.0 - alpha_prime));
  const auto [ix, tx] = locate(x, xv);
  // Linear in log tau.
  const auto [jt, ut] = locate(log_tau, std::log(tau_prime));
  Sample s;
  const std::size_t nx = x.size();
  const std::pair<std::size_t, double> corners[4] = {
      {jt * nx + ix, (1 - ut) * (1 - tx)},
      {jt * nx + ix + 1, (1 - ut) * tx},
      {(jt + 1) * nx + ix, ut * (1 - tx)},
      {(jt + 1) * nx + ix + 1, ut * tx}};
  for (const auto& [i, w] : corners) {
    const Node& n = nodes[i];
    s.R_e += w * n.R_e;
    s.T_down += w * n.T_down;
    s.T_up += w * n.T_up;
    s.R_up += w * n.R_up;
    accumulate(s.T_down_k, n.T_down_k, w);
    accumulate(s.T_up_k, n.T_up_k, w);
    accumulate(s.R_up_k, n.R_up_k, w);
  }
  // R_e: the shapes (profiles per unit total) are blended, geometrically where all four are
  // positive, and scaled by the blended total. (Near the dark end the totals of neighbouring
  // nodes differ up to three-fold; blending the raw profiles geometrically would lose 13 % of
  // the total between nodes.)
  const std::size_t n_rho = nodes[0].R_e_centre.size();
  s.R_e_centre.assign(n_rho, 0.0);
  s.log_R_e_centre.assign(n_rho, -kInf);
  const double log_total = s.R_e > 0 ? std::log(s.R_e) : -kInf;
  double log_node_total[4];
  for (int c = 0; c < 4; ++c) {
    const double t = nodes[corners[c].first].R_e;
    log_node_total[c] = t > 0 ? std::log(t) : -kInf;
  }
  for (std::size_t b = 0; b < n_rho; ++b) {
    bool positive = true;
    double lin = 0, log_sum = 0;
    for (int c = 0; c < 4; ++c) {
      const Node& n = nodes[corners[c].first];
      const double w = corners[c].second, v = n.R_e_centre[b];
      positive = positive && v > 0 && n.R_e > 0;
      if (n.R_e > 0) lin += w * v / n.R_e;
      if (positive) log_sum += w * (n.log_R_e_centre[b] - log_node_total[c]);
    }
    if (positive && s.R_e > 0) {
      s.log_R_e_centre[b] = log_sum + log_total;
      s.R_e_centre[b] = std::exp(s.log_R_e_centre[b]);
    } else {
      s.R_e_centre[b] = lin * s.R_e;
      if (s.R_e_centre[b] > 0) s.log_R_e_centre[b] = std::log(s.R_e_centre[b]);
    }
  }
  return s;
}

double TopLayerTable::rho_centre(std::size_t i) const {
  return i == 0 ? 0.5 * rho_edges[1] : std::sqrt(rho_edges[i] * rho_edges[i + 1]);
}

namespace {
// Between centre values i and i + 1 of a sample at log-radius fraction t: log-linear where both
// are positive, linear otherwise (zero or noise-level bins far out).
double between(const TopLayerTable::Sample& s, std::size_t i, double t) {
  const double a = s.R_e_centre[i], b = s.R_e_centre[i + 1];
  if (a > 0 && b > 0) return std::exp((1 - t) * s.log_R_e_centre[i] + t * s.log_R_e_centre[i + 1]);
  return (1 - t) * a + t * b;
}
}  // namespace

void TopLayerTable::Node::derive_centre_values(const std::vector<double>& edges) {
  const std::size_t n = R_e_rho.size();
  R_e_centre = R_e_rho;
  auto centre = [&](std::size_t i) {
    return i == 0 ? 0.5 * edges[1] : std::sqrt(edges[i] * edges[i + 1]);
  };
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double lo = R_e_rho[i - 1], hi = R_e_rho[i + 1];
    if (!(lo > 0 && hi > 0 && R_e_rho[i] > 0)) continue;
    // Local model f = f_c exp(-beta (rho - c)); its annulus average over [a, b] relative to f_c
    // is int_a^b e^{-beta (rho - c)} rho drho / ((b^2 - a^2) / 2) (Simpson, 8 intervals).
    const double beta = -std::log(hi / lo) / (centre(i + 1) - centre(i - 1));
    const double a = edges[i], b = edges[i + 1], c = centre(i);
    constexpr int m = 8;
    const double h = (b - a) / m;
    double sum = 0;
    for (int j = 0; j <= m; ++j) {
      const double r = a + j * h;
      sum += (j == 0 || j == m ? 1.0 : (j % 2 ? 4.0 : 2.0)) * std::exp(-beta * (r - c)) * r;
    }
    const double ratio = (sum * h / 3.0) / (0.5 * (b * b - a * a));
    R_e_centre[i] = R_e_rho[i] / ratio;
  }
  // Near the entry point (rho < kCore) the bins are small and hold few photons: their values
  // are replaced by a power law C rho^p, p fitted to them (least squares in log-log, weighted by
  // each bin's weight, clamped to [-1.9, 0]: integrable, not rising outwards), C keeping the
  // weight they hold together. Single and low-order scattering make R_e ~ 1/rho there.
  constexpr double kCore = 0.1;
  std::size_t m = 0;
  while (m < n && edges[m + 1] <= kCore * (1 + 1e-9)) ++m;
  double mass = 0, sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < m; ++i) {
    const double w = R_e_rho[i] * (edges[i + 1] * edges[i + 1] - edges[i] * edges[i]);
    mass += w;
    if (i == 0 || !(R_e_rho[i] > 0)) continue;
    const double x = std::log(centre(i)), y = std::log(R_e_rho[i]);
    sw += w;
    sx += w * x;
    sy += w * y;
    sxx += w * x * x;
    sxy += w * x * y;
  }
  if (m > 2 && mass > 0 && sw > 0) {
    const double den = sw * sxx - sx * sx;
    const double p = std::clamp(den > 0 ? (sw * sxy - sx * sy) / den : -1.0, -1.9, 0.0);
    // pi sum(avg (b^2 - a^2)) = int_0^edge C rho^p 2 pi rho drho = 2 pi C edge^(p+2) / (p + 2).
    const double C = mass * (p + 2.0) / (2.0 * std::pow(edges[m], p + 2.0));
    for (std::size_t i = 0; i < m; ++i) R_e_centre[i] = C * std::pow(centre(i), p);
  }
  log_R_e_centre.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    log_R_e_centre[i] = R_e_centre[i] > 0 ? std::log(R_e_centre[i]) : -kInf;
}

double TopLayerTable::R_e_at(const Sample& s, double rho) const {
  const std::size_t n = s.R_e_centre.size();
  if (rho <= rho_centre(0)) return s.R_e_centre[0];
  if (rho >= rho_centre(n - 1)) return 0.0;
  // Bin centres are evenly spaced in log rho from bin 1 on.
  std::size_t i;
  if (rho < rho_centre(1)) {
    i = 0;
  } else {
    const double q = log_rho_centre[2] - log_rho_centre[1];
    i = 1 + static_cast<std::size_t>((std::log(rho) - log_rho_centre[1]) / q);
    i = std::min(i, n - 2);
  }
  const double a = log_rho_centre[i], b = log_rho_centre[i + 1];
  const double t = (std::log(rho) - a) / (b - a);
  return between(s, i, t);
}

namespace {
// Where kappa lies among the nodes kappa_0 sinh(u_i), u evenly spaced from 0: the interval i and
// the position t in it (i == n - 1: beyond the last node).
struct NodePosition {
  std::size_t i = 0;
  double t = 0;
};
NodePosition node_position(const std::vector<double>& kappa, double kappa_0, double k) {
  const std::size_t n = kappa.size();
  if (k >= kappa.back()) return {n - 1, 0.0};
  const double du = std::asinh(kappa[1] / kappa_0);
  const double u = std::asinh(k / kappa_0) / du;
  const std::size_t i = std::min(static_cast<std::size_t>(u), n - 2);
  return {i, u - static_cast<double>(i)};
}
// Catmull-Rom (C1) in u. A transform of a radial function is even in kappa and smooth at 0;
// u is odd in kappa, so the node before the first is its mirror image (values[1] at u = -1).
// (Linear interpolation in u would put a |kappa| kink at 0, which the inverse transform turns
// into a spurious 1/r^3 tail far from the source.)
double interpolate(const std::vector<double>& values, NodePosition at) {
  const std::size_t n = values.size(), i = at.i;
  if (i == n - 1) return 0.0;
  const double p0 = i == 0 ? values[1] : values[i - 1];
  const double p1 = values[i], p2 = values[i + 1];
  const double p3 = i + 2 < n ? values[i + 2] : 2.0 * p2 - p1;
  return catmull_rom(p0, p1, p2, p3, at.t);
}
}  // namespace

double TopLayerTable::transform_at(const std::vector<double>& values, double k) const {
  return interpolate(values, node_position(kappa, kappa_0, k));
}

TopLayerTable::Transforms TopLayerTable::transforms_at(const Sample& s, double k) const {
  const NodePosition at = node_position(kappa, kappa_0, k);
  return {interpolate(s.T_down_k, at), interpolate(s.T_up_k, at), interpolate(s.R_up_k, at)};
}

double TopLayerTable::R_e_integral(const Sample& s) const {
  // 2 pi int R_e rho drho of the interpolant of R_e_at, in closed form: the constant core disc,
  // then per interval between bin centres c0 < c1 either a power law R = a (rho / c0)^p (log-
  // linear in log rho), whose integral is (b c1^2 - a c0^2) / (p + 2), or a linear function of
  // log rho where a value is not positive (Simpson).
  const double core = rho_centre(0);
  double total = s.R_e_centre[0] * std::numbers::pi * core * core;
  for (std::size_t i = 0; i + 1 < s.R_e_centre.size(); ++i) {
    const double c0 = rho_centre(i), c1 = rho_centre(i + 1);
    const double a = s.R_e_centre[i], b = s.R_e_centre[i + 1];
    const double L = std::log(c1 / c0);
    double part;
    if (a > 0 && b > 0) {
      const double q = s.log_R_e_centre[i + 1] - s.log_R_e_centre[i] + 2.0 * L;  // (p + 2) L
      part = std::abs(q) < 1e-9 ? a * c0 * c0 * L : (b * c1 * c1 - a * c0 * c0) * L / q;
    } else {
      constexpr int m = 8;  // even
      const double h = L / m;
      double sum = 0;
      for (int j = 0; j <= m; ++j) {
        const double t = static_cast<double>(j) / m;
        const double rho = c0 * std::exp(j * h);
        sum += (j == 0 || j == m ? 1.0 : (j % 2 ? 4.0 : 2.0)) * ((1 - t) * a + t * b) * rho * rho;
      }
      part = sum * h / 3.0;
    }
    total += 2.0 * std::numbers::pi * part;
  }
  return total;
}

std::string TopLayerTable::to_csv() const {
  std::ostringstream os;
  os << "# Spectral Skin: transport of a thin top layer (the epidermis) in reduced units,\n"
        "# tabulated by this project's Monte Carlo solver (include/skin/transport/top_layer_table.hpp\n"
        "# defines every column; docs/accurate-solver.md sec. 3 describes the method).\n";
  os << "# provenance: " << provenance << '\n';
  os << "# g: " << g << "\n# eta: " << eta << "\n# eta_above: " << eta_above << '\n';
  os << "# kappa_0: " << kappa_0 << '\n';
  os << "# x: " << format_number_list(x) << "\n# tau: " << format_number_list(tau) << "\n# kappa: " << format_number_list(kappa)
     << "\n# rho_edges: " << format_number_list(rho_edges) << '\n';
  os << "x,tau,R_e,T_down,T_up,R_up";
  for (std::size_t i = 0; i + 1 < rho_edges.size(); ++i) os << ",R_e_rho_" << i;
  for (const char* name : {"T_down_k_", "T_up_k_", "R_up_k_"})
    for (std::size_t i = 0; i < kappa.size(); ++i) os << ',' << name << i;
  os << '\n';
  char buf[32];
  for (std::size_t j = 0; j < tau.size(); ++j)
    for (std::size_t i = 0; i < x.size(); ++i) {
      const Node& n = nodes[j * x.size() + i];
      os << format_number_list({x[i], tau[j], n.R_e, n.T_down, n.T_up, n.R_up});
      for (const auto* v : {&n.R_e_rho, &n.T_down_k, &n.T_up_k, &n.R_up_k})
        for (double d : *v) {
          std::snprintf(buf, sizeof buf, ",%.5g", d);
          os << buf;
        }
      os << '\n';
    }
  return os.str();
}

TopLayerTable TopLayerTable::parse(std::string_view text, std::string_view source) {
  const std::string src(source);
  const auto meta = csv_metadata(text);
  TopLayerTable t;
  t.provenance = meta.count("provenance") ? meta.at("provenance") : "";
  t.g = metadata_number(meta, "g", src);
  t.eta = metadata_number(meta, "eta", src);
  t.eta_above = metadata_number(meta, "eta_above", src);
  t.kappa_0 = metadata_number(meta, "kappa_0", src);
  t.x = metadata_numbers(meta, "x", src);
  t.tau = metadata_numbers(meta, "tau", src);
  t.kappa = metadata_numbers(meta, "kappa", src);
  t.rho_edges = metadata_numbers(meta, "rho_edges", src);
  auto increasing = [&](const std::vector<double>& v, const char* key, std::size_t min_size) {
    if (v.size() < min_size) throw InputError(src + ": '" + key + "' has too few values");
    for (std::size_t i = 1; i < v.size(); ++i)
      if (!(v[i] > v[i - 1])) throw InputError(src + ": '" + key + "' must increase");
  };
  increasing(t.x, "x", 2);
  increasing(t.tau, "tau", 2);
  increasing(t.kappa, "kappa", 3);
  increasing(t.rho_edges, "rho_edges", 4);
  if (t.kappa.front() != 0.0 || t.rho_edges.front() != 0.0 || t.tau.front() <= 0 || t.x.front() < 0)
    throw InputError(src + ": kappa and rho_edges must start at 0, tau and x be positive");
  const Table data = parse_csv(text, src);
  const std::size_t n_rho = t.rho_edges.size() - 1, n_k = t.kappa.size();
  if (data.columns.size() != 6 + n_rho + 3 * n_k)
    throw InputError(src + ": expected " + std::to_string(6 + n_rho + 3 * n_k) + " columns, found " +
                     std::to_string(data.columns.size()));
  if (data.rows() != t.x.size() * t.tau.size())
    throw InputError(src + ": expected " + std::to_string(t.x.size() * t.tau.size()) +
                     " rows (x times tau), found " + std::to_string(data.rows()));
  t.nodes.resize(data.rows());
  for (std::size_t r = 0; r < data.rows(); ++r) {
    const std::size_t ix = r % t.x.size(), it = r / t.x.size();
    if (std::abs(data.data[0][r] - t.x[ix]) > 1e-6 || std::abs(data.data[1][r] / t.tau[it] - 1) > 1e-6)
      throw InputError(src + ": row " + std::to_string(r + 1) + " is not node (x, tau) = (" +
                       format_number(t.x[ix]) + ", " + format_number(t.tau[it]) + ")");
    Node& n = t.nodes[r];
    n.R_e = data.data[2][r];
    n.T_down = data.data[3][r];
    n.T_up = data.data[4][r];
    n.R_up = data.data[5][r];
    std::size_t c = 6;
    for (auto* v : {&n.R_e_rho}) {
      v->resize(n_rho);
      for (auto& d : *v) d = data.data[c++][r];
    }
    for (auto* v : {&n.T_down_k, &n.T_up_k, &n.R_up_k}) {
      v->resize(n_k);
      for (auto& d : *v) d = data.data[c++][r];
    }
    for (std::size_t col = 2; col < data.columns.size(); ++col)
      if (!std::isfinite(data.data[col][r]))
        throw InputError(src + ": row " + std::to_string(r + 1) + ", column " + data.columns[col] +
                         " is not a finite number");
  }
  t.derive();
  return t;
}

void TopLayerTable::derive() {
  log_tau.resize(tau.size());
  for (std::size_t i = 0; i < tau.size(); ++i) log_tau[i] = std::log(tau[i]);
  log_rho_centre.resize(rho_edges.size() - 1);
  for (std::size_t i = 0; i < log_rho_centre.size(); ++i) log_rho_centre[i] = std::log(rho_centre(i));
  for (Node& n : nodes) n.derive_centre_values(rho_edges);
}

const std::vector<TopLayerTable>& TopLayerTable::builtin_set() {
  static const std::vector<TopLayerTable> set = [] {
    std::vector<TopLayerTable> v;
    for (const char* name : {"top_layer_transport_g0.8.csv", "top_layer_transport_g0.9.csv",
                             "top_layer_transport_g0.95.csv"})
      v.push_back(parse(data::embedded(name), name));
    std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.g < b.g; });
    return v;
  }();
  return set;
}

const TopLayerTable& TopLayerTable::builtin() {
  for (const auto& t : builtin_set())
    if (t.g == 0.9) return t;
  return builtin_set().front();
}

bool TopLayerTable::same_grid(const TopLayerTable& o) const {
  return x == o.x && tau == o.tau && kappa == o.kappa && kappa_0 == o.kappa_0 &&
         rho_edges == o.rho_edges;
}

TopLayerTable::Sample TopLayerTable::blend(const Sample& a, const Sample& b, double w) {
  Sample s;
  s.R_e = (1 - w) * a.R_e + w * b.R_e;
  s.T_down = (1 - w) * a.T_down + w * b.T_down;
  s.T_up = (1 - w) * a.T_up + w * b.T_up;
  s.R_up = (1 - w) * a.R_up + w * b.R_up;
  auto lin = [w](const std::vector<double>& u, const std::vector<double>& v) {
    std::vector<double> out(u.size());
    for (std::size_t i = 0; i < u.size(); ++i) out[i] = (1 - w) * u[i] + w * v[i];
    return out;
  };
  s.T_down_k = lin(a.T_down_k, b.T_down_k);
  s.T_up_k = lin(a.T_up_k, b.T_up_k);
  s.R_up_k = lin(a.R_up_k, b.R_up_k);
  s.R_e_centre = lin(a.R_e_centre, b.R_e_centre);
  s.log_R_e_centre.assign(s.R_e_centre.size(), -kInf);
  for (std::size_t i = 0; i < s.R_e_centre.size(); ++i) {
    if (a.R_e_centre[i] > 0 && b.R_e_centre[i] > 0) {
      s.log_R_e_centre[i] = (1 - w) * a.log_R_e_centre[i] + w * b.log_R_e_centre[i];
      s.R_e_centre[i] = std::exp(s.log_R_e_centre[i]);
    } else if (s.R_e_centre[i] > 0) {
      s.log_R_e_centre[i] = std::log(s.R_e_centre[i]);
    }
  }
  return s;
}

std::ostream& operator<<(std::ostream& os, const TopLayerTable& t) {
  return os << "TopLayerTable{g=" << t.g << ", eta=" << t.eta << ", eta_above=" << t.eta_above
            << ", x=" << t.x.size() << " nodes [" << t.x.front() << ", " << t.x.back()
            << "], tau=" << t.tau.size() << " nodes [" << t.tau.front() << ", " << t.tau.back()
            << "], kappa=" << t.kappa.size() << " nodes up to " << t.kappa.back()
            << ", rho bins=" << t.rho_edges.size() - 1 << '}';
}

}  // namespace skin::accurate
