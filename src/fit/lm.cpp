#include "lm.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace skin::fit::detail {

Eigen::MatrixXd jacobian(const LmProblem& p, const Eigen::VectorXd& x, const Eigen::VectorXd& r) {
  const Eigen::Index n = x.size();
  Eigen::MatrixXd J(p.m, n);
  Eigen::VectorXd xp = x, rp(p.m);
  for (Eigen::Index j = 0; j < n; ++j) {
    // Step inward at the upper bound so that the model is never evaluated outside the box.
    double h = p.h[j];
    if (x[j] + h > p.hi[j]) h = -h;
    xp[j] = x[j] + h;
    p.residual(xp, rp);
    if (!rp.allFinite() && x[j] - h >= p.lo[j] && x[j] - h <= p.hi[j]) {
      // The model is undefined on one side (a domain barrier): difference the other way.
      h = -h;
      xp[j] = x[j] + h;
      p.residual(xp, rp);
    }
    if (!rp.allFinite()) {
      J.col(j).setZero();  // no usable derivative: the LM holds this coordinate still
      xp[j] = x[j];
      continue;
    }
    J.col(j) = (rp - r) / h;
    xp[j] = x[j];
  }
  return J;
}

namespace {
Eigen::VectorXd clamp(Eigen::VectorXd x, const LmProblem& p) {
  return x.cwiseMax(p.lo).cwiseMin(p.hi);
}
}  // namespace

LmResult levenberg_marquardt(const LmProblem& p, Eigen::VectorXd x0, int max_iterations,
                             bool final_jacobian) {
  const Eigen::Index n = x0.size();
  LmResult res;
  res.x = clamp(std::move(x0), p);
  res.r.resize(p.m);
  p.residual(res.x, res.r);
  res.cost = res.r.squaredNorm();
  if (n == 0) {
    res.J.resize(p.m, 0);
    return res;
  }
  double mu = 1e-3, nu = 2.0;
  for (int it = 0; it < max_iterations; ++it) {
    res.iterations = it + 1;
    const Eigen::MatrixXd J = jacobian(p, res.x, res.r);
    const Eigen::MatrixXd A = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * res.r;
    Eigen::VectorXd d = A.diagonal();
    const double dmax = std::max(d.maxCoeff(), 1e-300);
    d = d.cwiseMax(1e-12 * dmax);  // Marquardt scaling; floor keeps the system definite
    bool accepted = false;
    for (int tries = 0; tries < 16 && !accepted; ++tries) {
      // Active set: a coordinate on a bound whose descent direction points outward is held.
      std::vector<bool> held(static_cast<std::size_t>(n), false);
      Eigen::VectorXd dx = Eigen::VectorXd::Zero(n);
      for (int pass = 0; pass < 2; ++pass) {
        std::vector<Eigen::Index> idx;
        for (Eigen::Index j = 0; j < n; ++j)
          if (!held[static_cast<std::size_t>(j)]) idx.push_back(j);
        const Eigen::Index k = static_cast<Eigen::Index>(idx.size());
        dx.setZero();
        if (k == 0) break;
        Eigen::MatrixXd Ak(k, k);
        Eigen::VectorXd gk(k);
        for (Eigen::Index a = 0; a < k; ++a) {
          gk[a] = g[idx[a]];
          for (Eigen::Index b = 0; b < k; ++b) Ak(a, b) = A(idx[a], idx[b]);
          Ak(a, a) += mu * d[idx[a]];
        }
        const Eigen::VectorXd s = Ak.ldlt().solve(-gk);
        for (Eigen::Index a = 0; a < k; ++a) dx[idx[a]] = s[a];
        bool changed = false;
        for (Eigen::Index j = 0; j < n; ++j) {
          const auto u = static_cast<std::size_t>(j);
          if (held[u]) continue;
          const double span = p.hi[j] - p.lo[j];
          if ((res.x[j] <= p.lo[j] + 1e-12 * span && dx[j] < 0) ||
              (res.x[j] >= p.hi[j] - 1e-12 * span && dx[j] > 0)) {
            held[u] = true;
            changed = true;
          }
        }
        if (!changed) break;
      }
      const Eigen::VectorXd x_new = clamp(res.x + dx, p);
      const Eigen::VectorXd step = x_new - res.x;
      Eigen::VectorXd r_new(p.m);
      p.residual(x_new, r_new);
      const double cost_new = r_new.squaredNorm();
      // Predicted decrease of |r|^2 for the (projected) step: -2 g.dx - dx.A.dx.
      const double predicted = -2.0 * g.dot(step) - step.dot(A * step);
      if (std::isfinite(cost_new) && cost_new < res.cost) {
        const double gain = (res.cost - cost_new) / std::max(res.cost, 1e-300);
        // Nielsen's damping update (Madsen, Nielsen & Tingleff 2004, eq 3.16).
        const double rho = predicted > 0 ? (res.cost - cost_new) / predicted : 0.5;
        mu *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
        mu = std::max(mu, 1e-15);
        nu = 2.0;
        // Converged when the step is far inside the parameters' own uncertainty (1 % of one
        // standard deviation from s^2 (J^T J)^-1: further iterations cannot matter), or tiny
        // against the search interval, or the cost stalls. The first matters for poor fits
        // (large residuals), where Gauss-Newton converges only linearly.
        bool small = true;
        const double s2 = cost_new / static_cast<double>(std::max<Eigen::Index>(p.m - n, 1));
        Eigen::LDLT<Eigen::MatrixXd> ldlt(A);
        for (Eigen::Index j = 0; j < n && small; ++j) {
          Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
          e[j] = 1.0;
          const double var = s2 * ldlt.solve(e)[j];
          const double rel = std::abs(step[j]) / (p.hi[j] - p.lo[j]);
          small = rel < 1e-7 || (std::isfinite(var) && var > 0 && step[j] * step[j] < 1e-4 * var);
        }
        res.x = x_new;
        res.r = r_new;
        res.cost = cost_new;
        accepted = true;
        if (small || gain < 1e-9) {
          res.converged = true;
          if (final_jacobian) res.J = jacobian(p, res.x, res.r);
          return res;
        }
      } else {
        mu *= nu;
        nu *= 2.0;
      }
    }
    if (!accepted) {  // no decrease at any damping: at a (local) minimum
      res.converged = true;
      break;
    }
  }
  if (final_jacobian) res.J = jacobian(p, res.x, res.r);
  return res;
}

Eigen::VectorXd standard_errors(const Eigen::MatrixXd& J, double cost) {
  const Eigen::Index m = J.rows(), n = J.cols();
  if (m <= n) return Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity());
  return standard_errors_scaled(J, cost / static_cast<double>(m - n));
}

namespace {
// A variance that rounding has made zero or negative (a nearly singular J^T J) says the
// parameter is not determined, not that it is known exactly: infinity, not 0.
double standard_error(double variance) {
  return variance > 0 ? std::sqrt(variance) : std::numeric_limits<double>::infinity();
}
}  // namespace

Eigen::VectorXd standard_errors_scaled(const Eigen::MatrixXd& J, double s2) {
  const Eigen::Index n = J.cols();
  Eigen::VectorXd se = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity());
  if (J.rows() == 0) return se;
  const Eigen::MatrixXd A = J.transpose() * J;
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(A);
  cod.setThreshold(1e-12);
  if (cod.rank() < n) {
    // Unidentifiable directions: report infinity for the coordinates that take part in them.
    const Eigen::MatrixXd cov = s2 * cod.pseudoInverse();
    Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
    lu.setThreshold(1e-12);
    const Eigen::MatrixXd null = lu.kernel();
    for (Eigen::Index j = 0; j < n; ++j)
      se[j] = null.row(j).cwiseAbs().maxCoeff() > 1e-6 ? std::numeric_limits<double>::infinity()
                                                       : standard_error(cov(j, j));
    return se;
  }
  const Eigen::MatrixXd cov = s2 * A.inverse();
  for (Eigen::Index j = 0; j < n; ++j) se[j] = standard_error(cov(j, j));
  return se;
}

}  // namespace skin::fit::detail
