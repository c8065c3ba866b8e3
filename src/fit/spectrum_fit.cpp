// Spectrum fit: coarse table search over (C_m, beta_m, C_h), then bounded Levenberg-Marquardt
// from the best few table entries (docs/fit.md).
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <numeric>
#include <ostream>

#include <tbb/parallel_for.h>

#include "lm.hpp"
#include "skin/fit/fit.hpp"
#include "skin/fit/color_fit.hpp"
#include "skin/color/color.hpp"
#include "skin/physics/spectrum.hpp"
#include "skin/transport/diffusion.hpp"
#include "skin/physics/fresnel.hpp"
#include "skin/util/error.hpp"
#include "skin/transport/model.hpp"
#include "skin/transport/port.hpp"
#include "skin/transport/stack.hpp"
#include "skin/util/error.hpp"

namespace skin::fit {

using skin::util::InputError;
using skin::util::format_number;
using skin::util::require_in_range;

using skin::physics::LayerStack;
using skin::physics::SkinParameters;
using skin::physics::fresnel_dielectric;
using skin::physics::skin_layer_stack;

ForwardModel forward_model(const transport::Model& model) {
  return [&model](const SkinParameters& p, double lambda) {
    const LayerStack stack = skin_layer_stack(p, lambda);
    // Outside the model's range for totals (the multipole in an epidermis thinner than z_r,
    // where its transmittance changes sign discontinuously and R_d jumps; docs/fit.md,
    // "Validity") the fit sees NaN and treats it as a barrier.
    if (!model.validity(stack).totals) return std::numeric_limits<double>::quiet_NaN();
    return model.R_d(stack);
  };
}

ForwardModel forward_model(std::string_view solver) {
  return forward_model(transport::find_model(solver));
}

ForwardModel forward_model_through_port(const transport::Model& model, double port_radius, double beam_radius) {
  const transport::PortCollection check(port_radius, beam_radius);  // the radii, validated now
  return [&model, port_radius, beam_radius](const SkinParameters& p, double lambda) {
    const LayerStack stack = skin_layer_stack(p, lambda);
    // Outside the model's totals, or where its profile would be solved (~0.6 s a wavelength
    // instead of microseconds read: a fit calls it thousands of times), the fit sees a wall.
    if (!model.validity(stack).totals || model.response_is_solved(stack))
      return std::numeric_limits<double>::quiet_NaN();
    thread_local std::unique_ptr<transport::PortCollection> port;  // its ProfileSolver is per thread
    if (!port || port->port_radius() != port_radius || port->beam_radius() != beam_radius)
      port = std::make_unique<transport::PortCollection>(port_radius, beam_radius);
    return port->collected(*model.response(stack));
  };
}

double FitResult::uncertainty_of(Parameter p) const {
  for (std::size_t i = 0; i < free.size(); ++i)
    if (free[i] == p) return uncertainty[i];
  throw InputError("parameter '" + flag(p) + "' was not fitted");
}

std::ostream& operator<<(std::ostream& os, const FitResult& r) {
  os << "FitResult{rms=" << r.rms;
  for (std::size_t i = 0; i < r.free.size(); ++i)
    os << ", " << key(r.free[i]) << '=' << get(r.parameters, r.free[i]) << "+-" << r.uncertainty[i]
       << (r.at_bound[i] ? "(bound)" : "");
  if (r.specular > 0) os << ", specular=" << r.specular;
  return os << ", iterations=" << r.iterations << ", starts=" << r.starts << '}';
}

namespace {

bool is_core(Parameter p) {
  return p == Parameter::melanin || p == Parameter::melanin_blend || p == Parameter::hemoglobin ||
         p == Parameter::oiliness;
}

double specular_albedo(const SpectrumFitOptions& o) {
  // Fresnel reflectance at normal incidence, ((eta - 1) / (eta + 1))^2 = 0.0278 for eta 1.4:
  // the directional albedo of the rho_s = 1 surface lobe seen by a near-normal measurement.
  return o.specular_albedo >= 0 ? o.specular_albedo
                                : fresnel_dielectric(1.0, 1.0, o.start.eta);
}

// Table nodes of a core parameter within its bounds: geometric towards small fractions (R_d
// responds to C_m and C_h roughly logarithmically), linear for beta_m.
std::vector<double> nodes(Parameter p, Bounds b) {
  std::vector<double> v;
  if (p == Parameter::melanin_blend) {
    for (int i = 0; i <= 4; ++i) v.push_back(b.lo + (b.hi - b.lo) * i / 4.0);
    return v;
  }
  const int n = 12;
  const double a = std::max(b.lo, b.hi * 2e-3);
  if (b.lo < a) v.push_back(b.lo);
  for (int i = 0; i < n; ++i) v.push_back(a * std::pow(b.hi / a, i / double(n - 1)));
  return v;
}

constexpr double kTableStep = 10.0;  // [nm] coarse table sampling, 400-700 nm

// CIEDE2000 between two spectra sampled at `lambda` (reflectance_lab of each).
double spectrum_delta_e(const std::vector<double>& lambda, const std::vector<double>& a,
                        const std::vector<double>& b) {
  return color::delta_e_2000(reflectance_lab(lambda, a), reflectance_lab(lambda, b));
}

}  // namespace

struct SpectrumFitter::Impl {
  SpectrumFitOptions opt;
  ForwardModel model;
  double F = 0;                    // specular albedo
  std::vector<Parameter> core;     // free core parameters among melanin, blend, hemoglobin
  bool fit_oiliness = false;
  std::vector<Parameter> extended;  // free non-core parameters
  std::vector<Bounds> bounds;       // per opt.free

  // Coarse table: per entry, the core values and R_d on table_lambda.
  mutable std::once_flag once;
  mutable std::vector<double> table_lambda;
  mutable std::vector<std::vector<double>> table_values;
  mutable std::vector<std::vector<int>> table_index;
  mutable std::vector<std::vector<double>> table_R;

  Bounds bounds_of(Parameter p) const {
    for (const auto& [q, b] : opt.bounds)
      if (q == p) return b;
    return opt.fit_model == FitModel::extended ? prior_bounds(p) : default_bounds(p);
  }
  // The free parameters with a Gaussian prior term (extended model only), in opt.free's order.
  std::vector<Parameter> prior_terms(const std::vector<Parameter>& which) const {
    std::vector<Parameter> v;
    if (opt.fit_model != FitModel::extended) return v;
    for (Parameter p : which)
      if (has_prior_centre(p)) v.push_back(p);
    return v;
  }

  void build_table() const {
    for (double l = 400; l <= 700 + 1e-9; l += kTableStep) table_lambda.push_back(l);
    std::vector<std::vector<double>> axes;
    for (Parameter p : core) axes.push_back(nodes(p, bounds_of(p)));
    std::size_t total = 1;
    for (const auto& a : axes) total *= a.size();
    table_values.assign(total, {});
    table_index.assign(total, {});
    for (std::size_t e = 0; e < total; ++e) {
      std::size_t rest = e;
      for (const auto& a : axes) {
        table_index[e].push_back(static_cast<int>(rest % a.size()));
        table_values[e].push_back(a[rest % a.size()]);
        rest /= a.size();
      }
    }
    table_R.assign(total, std::vector<double>(table_lambda.size()));
    tbb::parallel_for(std::size_t(0), total, [&](std::size_t e) {
      SkinParameters p = opt.start;
      for (std::size_t k = 0; k < core.size(); ++k) set(p, core[k], table_values[e][k]);
      for (std::size_t i = 0; i < table_lambda.size(); ++i) table_R[e][i] = model(p, table_lambda[i]);
    });
  }

  // Model reflectance on the given wavelengths.
  void evaluate(const SkinParameters& p, const std::vector<double>& lambda, double* out) const {
    const double s = opt.includes_specular ? p.oiliness * F : 0.0;
    for (std::size_t i = 0; i < lambda.size(); ++i) out[i] = s + (1.0 - s) * model(p, lambda[i]);
  }

  // LM over the parameters `which` (subset of opt.free), from `start`.
  detail::LmResult run_lm(const std::vector<Parameter>& which, const SkinParameters& start,
                          const std::vector<double>& lambda, const std::vector<double>& R,
                          SkinParameters& out, int max_iterations = -1,
                          bool final_jacobian = true) const {
    const auto n = static_cast<Eigen::Index>(which.size());
    const std::vector<Parameter> priors = prior_terms(which);
    const auto m_data = static_cast<Eigen::Index>(lambda.size());
    detail::LmProblem prob;
    prob.m = m_data + static_cast<Eigen::Index>(priors.size());
    prob.lo.resize(n);
    prob.hi.resize(n);
    prob.h.resize(n);
    Eigen::VectorXd x0(n);
    for (Eigen::Index j = 0; j < n; ++j) {
      const Bounds b = bounds_of(which[j]);
      prob.lo[j] = b.lo;
      prob.hi[j] = b.hi;
      prob.h[j] = 1e-6 * (b.hi - b.lo);
      x0[j] = get(start, which[j]);
    }
    prob.residual = [&](const Eigen::VectorXd& x, Eigen::VectorXd& r) {
      SkinParameters p = start;
      for (Eigen::Index j = 0; j < n; ++j) set(p, which[j], x[j]);
      evaluate(p, lambda, r.data());
      for (Eigen::Index i = 0; i < m_data; ++i) r[i] -= R[static_cast<std::size_t>(i)];
      // Gaussian prior terms: weight x (u - u_centre) in the prior range's coordinate.
      for (std::size_t k = 0; k < priors.size(); ++k) {
        const Parameter q = priors[k];
        r[m_data + static_cast<Eigen::Index>(k)] =
            kSpectrumPriorWeight * (prior_coordinate(q, get(p, q)) - prior_coordinate(q, q.info().prior_centre));
      }
    };
    detail::LmResult res = detail::levenberg_marquardt(
        prob, x0, max_iterations < 0 ? opt.max_iterations : max_iterations, final_jacobian);
    out = start;
    for (Eigen::Index j = 0; j < n; ++j) set(out, which[j], res.x[j]);
    return res;
  }
};

SpectrumFitter::SpectrumFitter(SpectrumFitOptions options) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  options.start.validate();
  m.opt = std::move(options);
  m.model = m.opt.model ? m.opt.model : forward_model(transport::default_model());
  m.F = specular_albedo(m.opt);
  require_in_range("specular-albedo", m.F, 0.0, 1.0);
  if (m.opt.free.empty()) throw InputError("free parameters: the list is empty");
  check_bounds(m.opt.bounds);
  for (std::size_t i = 0; i < m.opt.free.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (m.opt.free[i] == m.opt.free[j])
        throw InputError("free parameter '" + flag(m.opt.free[i]) + "' is listed twice");
  const bool has_oil = std::find(m.opt.free.begin(), m.opt.free.end(), Parameter::oiliness) !=
                       m.opt.free.end();
  if (has_oil && !m.opt.includes_specular)
    throw InputError("free parameter 'oiliness' (rho_s) is only seen through the specular term: "
                     "use it with --includes-specular");
  if (m.opt.includes_specular && !has_oil) m.opt.free.push_back(Parameter::oiliness);
  for (Parameter p : m.opt.free) {
    const Bounds b = m.bounds_of(p);
    if (!(b.lo < b.hi) || !std::isfinite(b.lo) || !std::isfinite(b.hi))
      throw InputError("bounds of " + flag(p) + " = [" + format_number(b.lo) + ", " +
                       format_number(b.hi) + "] are invalid: need lo < hi");
    // The bounds must be valid parameter values themselves.
    SkinParameters lo = m.opt.start, hi = m.opt.start;
    set(lo, p, b.lo);
    set(hi, p, b.hi);
    lo.validate();
    hi.validate();
    if (p == Parameter::oiliness) m.fit_oiliness = true;
    else if (is_core(p)) m.core.push_back(p);
    else m.extended.push_back(p);
  }
  // Start values of free parameters: the prior centre under the extended model, clamped into
  // their bounds.
  for (Parameter p : m.opt.free) {
    if (m.opt.fit_model == FitModel::extended && has_prior_centre(p)) set(m.opt.start, p, p.info().prior_centre);
    const Bounds b = m.bounds_of(p);
    set(m.opt.start, p, std::clamp(get(m.opt.start, p), b.lo, b.hi));
  }
  if (m.opt.lambda_min >= m.opt.lambda_max)
    throw InputError("lambda-min = " + format_number(m.opt.lambda_min) +
                     " nm must be below lambda-max = " + format_number(m.opt.lambda_max) + " nm");
}
SpectrumFitter::~SpectrumFitter() = default;
SpectrumFitter::SpectrumFitter(SpectrumFitter&&) noexcept = default;
SpectrumFitter& SpectrumFitter::operator=(SpectrumFitter&&) noexcept = default;
const SpectrumFitOptions& SpectrumFitter::options() const { return impl_->opt; }
void SpectrumFitter::prepare() const { std::call_once(impl_->once, [this] { impl_->build_table(); }); }

FitResult SpectrumFitter::fit(const MeasuredSpectrum& meas) const {
  validate_spectrum(meas);
  prepare();
  const Impl& m = *impl_;
  // Samples to fit.
  std::vector<double> lambda, R;
  for (std::size_t i = 0; i < meas.R.size(); ++i)
    if (meas.wavelength_nm[i] >= m.opt.lambda_min && meas.wavelength_nm[i] <= m.opt.lambda_max) {
      lambda.push_back(meas.wavelength_nm[i]);
      R.push_back(meas.R[i]);
    }
  if (lambda.size() < std::max(kMinSamples, m.opt.free.size() + 2))
    throw InputError("spectrum '" + meas.name + "': " + std::to_string(lambda.size()) +
                     " samples within " + format_number(m.opt.lambda_min) + "-" +
                     format_number(m.opt.lambda_max) + " nm, too few for " +
                     std::to_string(m.opt.free.size()) + " free parameters");

  // Global stage: the measurement interpolated to the table's wavelengths it covers, compared
  // with every entry (the specular term, linear in rho_s, solved in closed form per entry).
  std::vector<std::size_t> tl;
  std::vector<double> tR;
  for (std::size_t i = 0; i < m.table_lambda.size(); ++i) {
    const double l = m.table_lambda[i];
    if (l < lambda.front() || l > lambda.back()) continue;
    const auto it = std::lower_bound(lambda.begin(), lambda.end(), l);
    const std::size_t k = static_cast<std::size_t>(it - lambda.begin());
    double v = R[k];
    if (lambda[k] != l) {
      const double t = (l - lambda[k - 1]) / (lambda[k] - lambda[k - 1]);
      v = R[k - 1] + t * (R[k] - R[k - 1]);
    }
    tl.push_back(i);
    tR.push_back(v);
  }
  struct Candidate {
    double sse;
    std::size_t entry;
    double oil;
  };
  std::vector<Candidate> cand(m.table_R.size());
  for (std::size_t e = 0; e < m.table_R.size(); ++e) {
    double oil = m.opt.start.oiliness;
    if (m.fit_oiliness) {
      double num = 0, den = 0;
      for (std::size_t i = 0; i < tl.size(); ++i) {
        const double Rd = m.table_R[e][tl[i]], a = m.F * (1 - Rd);
        num += a * (tR[i] - Rd);
        den += a * a;
      }
      oil = den > 0 ? std::clamp(num / den, 0.0, 1.0) : 0.0;
    }
    const double s = m.opt.includes_specular ? oil * m.F : 0.0;
    double sse = 0;
    for (std::size_t i = 0; i < tl.size(); ++i) {
      const double d = s + (1 - s) * m.table_R[e][tl[i]] - tR[i];
      sse += d * d;
    }
    cand[e] = {std::isfinite(sse) ? sse : std::numeric_limits<double>::infinity(), e, oil};
  }
  std::sort(cand.begin(), cand.end(), [](const Candidate& a, const Candidate& b) { return a.sse < b.sse; });
  // Up to 3 starts: the best entry and the next best ones that are not its table neighbours
  // (a different basin), and not much worse.
  std::vector<const Candidate*> starts;
  for (const auto& c : cand) {
    if (starts.size() >= 3 || c.sse > 4.0 * cand.front().sse + 1e-12) break;
    bool far = true;
    for (const Candidate* s : starts) {
      int dist = 0;
      for (std::size_t k = 0; k < m.core.size(); ++k)
        dist = std::max(dist, std::abs(m.table_index[c.entry][k] - m.table_index[s->entry][k]));
      if (dist < 2) far = false;
    }
    if (far) starts.push_back(&c);
  }

  // Stage 1 fits the core parameters (in the order of opt.free when nothing else is free, so
  // that the Jacobian's columns follow r.free).
  std::vector<Parameter> stage1 = m.core;
  if (m.fit_oiliness) stage1.push_back(Parameter::oiliness);
  if (m.extended.empty()) stage1 = m.opt.free;
  struct Solution {
    SkinParameters p;
    detail::LmResult lm;
  };
  // A race: every start gets a few LM iterations (in parallel), then the leader, and any start
  // that is still close to it, run to convergence. The ranking after 3 iterations is reliable
  // because each start already sits in its basin (they are table minima).
  constexpr int kRaceIterations = 3;
  std::vector<Solution> sols(starts.size());
  tbb::parallel_for(std::size_t(0), starts.size(), [&](std::size_t i) {
    SkinParameters s = m.opt.start;
    for (std::size_t k = 0; k < m.core.size(); ++k)
      set(s, m.core[k], m.table_values[starts[i]->entry][k]);
    s.oiliness = starts[i]->oil;
    sols[i].lm = m.run_lm(stage1, s, lambda, R, sols[i].p, kRaceIterations, false);
  });
  int runs = static_cast<int>(starts.size());
  std::sort(sols.begin(), sols.end(), [](const Solution& a, const Solution& b) { return a.lm.cost < b.lm.cost; });
  // Finalists: the leader and the starts within 10 % of its cost that are not heading into the
  // same minimum (all coordinates within 3 % of their search interval of a better start).
  {
    std::vector<Solution> finalists;
    for (auto& sol : sols) {
      if (!finalists.empty() && !(sol.lm.cost < 1.1 * finalists.front().lm.cost)) break;
      bool same = false;
      for (const auto& f : finalists) {
        bool close = true;
        for (Parameter q : stage1) {
          const Bounds b = m.bounds_of(q);
          close = close && std::abs(get(sol.p, q) - get(f.p, q)) < 0.03 * (b.hi - b.lo);
        }
        same = same || close;
      }
      if (!same) finalists.push_back(std::move(sol));
    }
    sols = std::move(finalists);
  }
  tbb::parallel_for(std::size_t(0), sols.size(), [&](std::size_t i) {
    const int done = sols[i].lm.iterations;
    sols[i].lm = m.run_lm(stage1, sols[i].p, lambda, R, sols[i].p, -1, true);
    sols[i].lm.iterations += done;
  });
  std::sort(sols.begin(), sols.end(), [](const Solution& a, const Solution& b) { return a.lm.cost < b.lm.cost; });

  // Extended stage: all free parameters from the best two stage-1 solutions.
  Solution best = sols.front();
  if (!m.extended.empty()) {
    // Starts: the best two stage-1 solutions, and for a free scattering scale the best one with
    // sigma_s' doubled and tripled (the red end of light skin needs more scattering than eq 8
    // gives, a basin the local search does not reach from 1).
    std::vector<SkinParameters> starts2;
    for (std::size_t i = 0; i < std::min<std::size_t>(2, sols.size()); ++i) starts2.push_back(sols[i].p);
    if (std::find(m.extended.begin(), m.extended.end(), Parameter::scattering_scale) != m.extended.end()) {
      const Bounds b = m.bounds_of(Parameter::scattering_scale);
      for (double f : {2.0, 3.0}) {
        SkinParameters s = sols.front().p;
        s.scattering_scale = std::clamp(s.scattering_scale * f, b.lo, b.hi);
        starts2.push_back(s);
      }
    }
    bool first = true;
    for (const SkinParameters& s : starts2) {
      Solution sol;
      sol.lm = m.run_lm(m.opt.free, s, lambda, R, sol.p);
      ++runs;
      if (!std::isfinite(sol.lm.cost)) continue;
      if (first || sol.lm.cost < best.lm.cost) best = std::move(sol);
      first = false;
    }
  }

  FitResult r;
  r.parameters = best.p;
  r.free = m.opt.free;
  r.starts = runs;
  r.iterations = best.lm.iterations;
  r.wavelength_nm = lambda;
  r.measured = R;
  r.fitted.resize(lambda.size());
  m.evaluate(best.p, lambda, r.fitted.data());
  double sse = 0;
  for (std::size_t i = 0; i < R.size(); ++i) sse += (r.fitted[i] - R[i]) * (r.fitted[i] - R[i]);
  r.rms = std::sqrt(sse / static_cast<double>(R.size()));
  r.specular = m.opt.includes_specular ? best.p.oiliness * m.F : 0.0;
  r.fit_model = m.opt.fit_model;
  r.delta_e = spectrum_delta_e(lambda, R, r.fitted);
  r.outside_gamut = r.rms >= kGoodFitRms;
  // Uncertainty from the Jacobian of the final LM run, whose columns follow its `which`: the
  // extended stage ran over opt.free; stage 1 alone ran over stage1 == opt.free.
  // The rows of J beyond the samples are the prior terms: the residual variance is the samples'
  // (s^2 = SSR / (m - n)); the prior rows enter J^T J.
  const double s2 = sse / static_cast<double>(std::max<std::ptrdiff_t>(
                              static_cast<std::ptrdiff_t>(R.size()) - static_cast<std::ptrdiff_t>(r.free.size()), 1));
  const Eigen::VectorXd se = m.opt.fit_model == FitModel::extended
                                 ? detail::standard_errors_scaled(best.lm.J, s2)
                                 : detail::standard_errors(best.lm.J, best.lm.cost);
  for (std::size_t j = 0; j < r.free.size(); ++j) {
    r.uncertainty.push_back(se[static_cast<Eigen::Index>(j)]);
    const Bounds b = m.bounds_of(r.free[j]);
    const double v = get(r.parameters, r.free[j]);
    r.at_bound.push_back(v <= b.lo + 1e-9 * (b.hi - b.lo) || v >= b.hi - 1e-9 * (b.hi - b.lo));
  }
  return r;
}

color::Lab reflectance_lab(const std::vector<double>& lambda, const std::vector<double>& R) {
  static const color::Colorimetry cm{physics::WavelengthGrid{}};
  static const std::vector<double> grid = physics::WavelengthGrid{}.values();
  const auto& w = cm.srgb_weights();
  color::Rgb c;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const double l = grid[i];
    double v;
    if (l <= lambda.front()) v = R.front();
    else if (l >= lambda.back()) v = R.back();
    else {
      const auto k = static_cast<std::size_t>(std::lower_bound(lambda.begin(), lambda.end(), l) - lambda.begin());
      const double t = (l - lambda[k - 1]) / (lambda[k] - lambda[k - 1]);
      v = R[k - 1] + t * (R[k] - R[k - 1]);
    }
    c.r += w[i][0] * v;
    c.g += w[i][1] * v;
    c.b += w[i][2] * v;
  }
  return color::summarize_rgb(cm, c).lab;
}

FitResult fit_spectrum(const MeasuredSpectrum& m, const SpectrumFitOptions& options) {
  return SpectrumFitter(options).fit(m);
}

std::vector<double> model_reflectance(const SkinParameters& p, const std::vector<double>& lambda,
                                      const SpectrumFitOptions& options) {
  const ForwardModel model = options.model ? options.model : forward_model(transport::default_model());
  const double s = options.includes_specular ? p.oiliness * specular_albedo(options) : 0.0;
  std::vector<double> out;
  for (double l : lambda) out.push_back(s + (1.0 - s) * model(p, l));
  return out;
}

}  // namespace skin::fit
