#pragma once
// Bounded Levenberg-Marquardt (internal to skin_fit; Eigen stays out of the public headers).
// Minimises |r(x)|^2 for lo <= x <= hi: Marquardt's scaled damping (J^T J + mu diag(J^T J)) dx =
// -J^T r, steps projected onto the box, coordinates held on a bound when the step pushes them
// outward (an active set), forward-difference Jacobian stepping inward at the upper bound.
// References: Marquardt 1963; Nocedal & Wright, Numerical Optimization, 2nd ed., section 10.3.
#include <Eigen/Dense>
#include <functional>

namespace skin::fit::detail {

struct LmProblem {
  // Fills r (size m) for x (size n). Must not throw for x inside the box.
  std::function<void(const Eigen::VectorXd& x, Eigen::VectorXd& r)> residual;
  Eigen::Index m = 0;
  Eigen::VectorXd lo, hi;  // box
  Eigen::VectorXd h;       // finite-difference step per coordinate (absolute)
};

struct LmResult {
  Eigen::VectorXd x, r;
  Eigen::MatrixXd J;  // Jacobian at x
  double cost = 0;    // |r|^2
  int iterations = 0;
  bool converged = false;  // stopped by a convergence test, not by max_iterations
};

// final_jacobian = false skips the Jacobian at the result (J stays empty): for short runs whose
// result only ranks starting points.
LmResult levenberg_marquardt(const LmProblem& p, Eigen::VectorXd x0, int max_iterations,
                             bool final_jacobian = true);

// Jacobian by forward differences (backward at the upper bound).
Eigen::MatrixXd jacobian(const LmProblem& p, const Eigen::VectorXd& x, const Eigen::VectorXd& r);

// One standard deviation per coordinate from covariance s^2 (J^T J)^-1, s^2 = |r|^2 / (m - n)
// (the unbiased residual variance); coordinates with no information get +infinity.
Eigen::VectorXd standard_errors(const Eigen::MatrixXd& J, double cost);
// The same with the residual variance s^2 given (covariance s^2 (J^T J)^-1): for problems whose
// rows include prior terms, or whose residuals have a known scale.
Eigen::VectorXd standard_errors_scaled(const Eigen::MatrixXd& J, double s2);

}  // namespace skin::fit::detail
