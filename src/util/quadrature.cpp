#include "skin/util/quadrature.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <map>
#include <mutex>
#include <utility>

#include "skin/util/error.hpp"

namespace skin::util {
namespace {

using Mat = Eigen::MatrixXd;
using Vec = Eigen::VectorXd;

// Gauss-Legendre (radau = false) or Gauss-Radau with the fixed node +1 (radau = true) on
// [-1, 1], by the Golub-Welsch eigenvalue method (Golub & Welsch 1969; Golub 1973 for the
// prescribed node: the last diagonal entry of the Jacobi matrix is changed so that +1 becomes an
// eigenvalue). Nodes ascending. Cached: the rules depend only on (n, radau).
const QuadratureRule& rule(int n, bool radau) {
  SKIN_ASSERT(n >= 1, "quadrature rule with n=" + std::to_string(n) + " nodes");
  static std::mutex mutex;
  static std::map<std::pair<int, bool>, QuadratureRule> cache;
  std::lock_guard<std::mutex> lock(mutex);
  auto it = cache.find({n, radau});
  if (it != cache.end()) return it->second;
  QuadratureRule rule;
  if (n == 1) {
    rule.x = {radau ? 1.0 : 0.0};
    rule.w = {2.0};
  } else {
    Mat J = Mat::Zero(n, n);
    auto beta = [](int k) {
      const double kk = static_cast<double>(k);
      return kk / std::sqrt(4.0 * kk * kk - 1.0);
    };
    for (int k = 1; k < n; ++k) J(k - 1, k) = J(k, k - 1) = beta(k);
    if (radau) {
      // (J_{n-1} - a I) delta = beta_{n-1}^2 e_{n-1};  alpha_n = a + delta_{n-1}, a = +1.
      const Mat Jm = J.topLeftCorner(n - 1, n - 1) - Mat::Identity(n - 1, n - 1);
      Vec rhs = Vec::Zero(n - 1);
      rhs(n - 2) = beta(n - 1) * beta(n - 1);
      const Vec delta = Jm.partialPivLu().solve(rhs);
      J(n - 1, n - 1) = 1.0 + delta(n - 2);
    }
    Eigen::SelfAdjointEigenSolver<Mat> es(J);
    rule.x.resize(static_cast<std::size_t>(n));
    rule.w.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      rule.x[static_cast<std::size_t>(i)] = es.eigenvalues()(i);
      rule.w[static_cast<std::size_t>(i)] = 2.0 * es.eigenvectors()(0, i) * es.eigenvectors()(0, i);
    }
    if (radau) rule.x.back() = 1.0;  // exactly, not 1 - 1e-16
  }
  return cache.emplace(std::pair{n, radau}, std::move(rule)).first->second;
}

}  // namespace

const QuadratureRule& gauss_legendre(int n) { return rule(n, false); }
const QuadratureRule& gauss_radau(int n) { return rule(n, true); }

}  // namespace skin::util
