// The random-walk response of an index-matched half-space (random_walk_table.hpp).
#include "skin/transport/random_walk_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <ostream>
#include <sstream>

#include "skin/util/error.hpp"
#include "skin/util/interpolation.hpp"
#include "skin/util/table.hpp"

namespace skin::transport {

using skin::util::InputError;
using skin::util::Table;
using skin::util::csv_metadata;
using skin::util::format_number;
using skin::util::format_number_list;
using skin::util::locate;
using skin::util::metadata_numbers;
using skin::util::parse_csv;

namespace {

// Node index and weight of alpha, interpolating in log(1 - alpha).
std::pair<std::size_t, double> alpha_weight(const std::vector<double>& alpha, double a) {
  std::vector<double> x(alpha.size());
  // log(1 - alpha) decreases with alpha: interpolate in -log(1 - alpha), which increases.
  for (std::size_t i = 0; i < alpha.size(); ++i) x[i] = -std::log1p(-alpha[i]);
  const double v = -std::log1p(-std::clamp(a, alpha.front(), alpha.back()));
  return locate(x, v);
}

double lerp_at(const std::vector<double>& v, std::pair<std::size_t, double> w) {
  return (1.0 - w.second) * v[w.first] + w.second * v[w.first + 1];
}

}  // namespace

const RandomWalkTable& RandomWalkTable::builtin() {
  static const RandomWalkTable t = from_csv(util::data::embedded("random_walk_g0.csv"),
                                            "data/random_walk_g0.csv");
  return t;
}

RandomWalkTable RandomWalkTable::from_csv(std::string_view text, const std::string& source) {
  const auto meta = csv_metadata(text);
  RandomWalkTable t;
  if (const auto it = meta.find("provenance"); it != meta.end()) t.provenance = it->second;
  const auto g = metadata_numbers(meta, "g", source);
  if (g.size() != 1 || !(std::abs(g[0]) < 1))
    throw InputError(source + ": 'g' must be one number in (-1, 1)");
  t.g = g[0];
  t.rho_edges = metadata_numbers(meta, "rho_edges", source);
  if (t.rho_edges.size() < 3 || t.rho_edges.front() != 0.0)
    throw InputError(source + ": 'rho_edges' must start at 0 and hold at least 3 edges");
  for (std::size_t i = 1; i < t.rho_edges.size(); ++i)
    if (!(t.rho_edges[i] > t.rho_edges[i - 1]) || !(t.rho_edges[i] <= 1e6))
      throw InputError(source + ": 'rho_edges' must increase, up to at most 1e6 mean free paths");
  const Table data = parse_csv(text, source);
  const std::size_t bins = t.rho_edges.size() - 1;
  if (data.columns.size() != 3 + bins)
    throw InputError(source + ": expected " + std::to_string(3 + bins) +
                     " columns (alpha, R_d, R_d_se and one per annulus), found " +
                     std::to_string(data.columns.size()));
  t.alpha = data.data[data.column("alpha")];
  t.R_d = data.data[data.column("R_d")];
  t.R_d_se = data.data[data.column("R_d_se")];
  if (t.alpha.size() < 2) throw InputError(source + ": needs at least two rows");
  for (std::size_t i = 0; i < t.alpha.size(); ++i) {
    if (!(t.alpha[i] > 0 && t.alpha[i] < 1) || (i && !(t.alpha[i] > t.alpha[i - 1])))
      throw InputError(source + ": 'alpha' must increase within (0, 1)");
    // (found by fuzzing: a negative R_d was read and gave a negative reflectance)
    if (!(t.R_d[i] >= 0 && t.R_d[i] <= 1) || !(t.R_d_se[i] >= 0 && std::isfinite(t.R_d_se[i])))
      throw InputError(source + ": row " + std::to_string(i + 1) +
                       ": R_d must be in [0, 1] and R_d_se finite and >= 0");
    std::vector<double> f(bins);
    double sum = 0;
    for (std::size_t b = 0; b < bins; ++b) {
      f[b] = data.data[3 + b][i];
      if (!(f[b] >= 0)) throw InputError(source + ": a negative or missing fraction in row " +
                                         std::to_string(i + 1));
      sum += f[b];
    }
    // The annuli hold part of what leaves: at most R_d (to the 7 digits the table is written with).
    if (!(sum <= t.R_d[i] * (1 + 1e-5) + 1e-9))
      throw InputError(source + ": row " + std::to_string(i + 1) + ": the annuli's fractions add up to " +
                       format_number(sum) + ", more than R_d = " + format_number(t.R_d[i]));
    t.fraction.push_back(std::move(f));
  }
  return t;
}

std::string RandomWalkTable::to_csv() const {
  std::ostringstream os;
  os << "# Spectral Skin: random-walk subsurface response of an index-matched half-space\n"
        "# (Lambertian entry, Henyey-Greenstein phase function, exit on first crossing), per power\n"
        "# that entered; radii in mean free paths rho = sigma_t r. Defined in\n"
        "# include/skin/transport/random_walk_table.hpp; columns: alpha (single-scattering albedo),\n"
        "# R_d and its standard error, then the power leaving in each annulus of rho_edges.\n";
  os << "# provenance: " << provenance << '\n';
  os << "# g: " << format_number_list({g}) << '\n';
  os << "# rho_edges: " << format_number_list(rho_edges) << '\n';
  os << "alpha,R_d,R_d_se";
  for (std::size_t b = 0; b + 1 < rho_edges.size(); ++b) os << ",f_" << b;
  os << '\n';
  char buf[40];
  for (std::size_t i = 0; i < alpha.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%.9g,%.7g,%.3g", alpha[i], R_d[i], R_d_se[i]);
    os << buf;
    for (double f : fraction[i]) {
      std::snprintf(buf, sizeof buf, ",%.5g", f);
      os << buf;
    }
    os << '\n';
  }
  return os.str();
}

// Below the first node the walk is dominated by single scattering: R and every annulus's share
// vanish linearly with alpha (R = alpha x the single-scatter escape probability at alpha -> 0).
double RandomWalkTable::reflectance(double a) const {
  if (a < alpha.front()) return R_d.front() * std::max(a, 0.0) / alpha.front();
  return lerp_at(R_d, alpha_weight(alpha, a));
}

std::vector<double> RandomWalkTable::fractions(double a) const {
  if (a < alpha.front()) {
    std::vector<double> f = fraction.front();
    for (double& v : f) v *= std::max(a, 0.0) / alpha.front();
    return f;
  }
  const auto w = alpha_weight(alpha, a);
  std::vector<double> f(fraction[w.first].size());
  for (std::size_t b = 0; b < f.size(); ++b)
    f[b] = (1.0 - w.second) * fraction[w.first][b] + w.second * fraction[w.first + 1][b];
  return f;
}

double RandomWalkTable::mean_rho(double a) const {
  const std::vector<double> f = fractions(a);
  double sum = 0, moment = 0;
  for (std::size_t b = 0; b < f.size(); ++b) {
    const double r0 = rho_edges[b], r1 = rho_edges[b + 1];
    // Area-weighted mean radius of the annulus: (2/3) (r1^3 - r0^3) / (r1^2 - r0^2).
    const double centre = 2.0 / 3.0 * (r1 * r1 * r1 - r0 * r0 * r0) / (r1 * r1 - r0 * r0);
    sum += f[b];
    moment += f[b] * centre;
  }
  return sum > 0 ? moment / sum : 0.0;
}

std::vector<double> RandomWalkTable::density(double a, const std::vector<double>& rho) const {
  const std::vector<double> f = fractions(a);
  const std::size_t bins = f.size();
  std::vector<double> log_centre(bins), value(bins);
  for (std::size_t b = 0; b < bins; ++b) {
    const double r0 = rho_edges[b], r1 = rho_edges[b + 1];
    log_centre[b] = std::log(b == 0 ? 0.5 * r1 : std::sqrt(r0 * r1));
    value[b] = f[b] / (std::numbers::pi * (r1 * r1 - r0 * r0));
  }
  std::vector<double> out(rho.size());
  for (std::size_t j = 0; j < rho.size(); ++j) {
    if (!(rho[j] > 0) || rho[j] >= rho_edges.back()) {
      out[j] = rho[j] > 0 ? 0.0 : value.front();
      continue;
    }
    const auto w = locate(log_centre, std::log(rho[j]));
    // Interpolate the logarithm where both neighbours are positive (the density falls
    // exponentially), linearly otherwise.
    const double v0 = value[w.first], v1 = value[w.first + 1];
    out[j] = v0 > 0 && v1 > 0 ? std::exp((1 - w.second) * std::log(v0) + w.second * std::log(v1))
                              : (1 - w.second) * v0 + w.second * v1;
  }
  return out;
}

std::ostream& operator<<(std::ostream& os, const RandomWalkTable& t) {
  return os << "RandomWalkTable{g=" << t.g << ", alpha " << t.alpha.front() << ".."
            << t.alpha.back() << " (" << t.alpha.size() << " nodes), " << t.rho_edges.size() - 1
            << " annuli to rho=" << t.rho_edges.back() << '}';
}

}  // namespace skin::transport
