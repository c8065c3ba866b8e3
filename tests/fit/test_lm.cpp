// The bounded Levenberg-Marquardt against closed forms: an exactly solvable model, a minimum
// outside the box, and standard errors against ordinary least squares' textbook formula.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "lm.hpp"

using skin::fit::detail::LmProblem;

namespace {
LmProblem exp_problem(const std::vector<double>& x, const std::vector<double>& y) {
  LmProblem p;
  p.m = static_cast<Eigen::Index>(x.size());
  p.lo = Eigen::Vector2d(0.0, 0.0);
  p.hi = Eigen::Vector2d(10.0, 10.0);
  p.h = Eigen::Vector2d(1e-7, 1e-7);
  p.residual = [x, y](const Eigen::VectorXd& q, Eigen::VectorXd& r) {
    for (std::size_t i = 0; i < x.size(); ++i) r[static_cast<Eigen::Index>(i)] = q[0] * std::exp(-q[1] * x[i]) - y[i];
  };
  return p;
}
}  // namespace

TEST(LevenbergMarquardt, RecoversNoiseFreeExponential) {
  std::vector<double> x, y;
  for (int i = 0; i < 20; ++i) {
    x.push_back(0.1 * i);
    y.push_back(2.5 * std::exp(-1.3 * x.back()));
  }
  const auto res = skin::fit::detail::levenberg_marquardt(exp_problem(x, y), Eigen::Vector2d(1.0, 5.0), 100);
  EXPECT_NEAR(res.x[0], 2.5, 1e-6);
  EXPECT_NEAR(res.x[1], 1.3, 1e-6);
  EXPECT_LT(res.cost, 1e-12);
}

TEST(LevenbergMarquardt, StopsOnTheBoundWhenTheMinimumIsOutside) {
  std::vector<double> x, y;
  for (int i = 0; i < 20; ++i) {
    x.push_back(0.1 * i);
    y.push_back(12.0 * std::exp(-1.3 * x.back()));  // amplitude 12 > upper bound 10
  }
  const auto res = skin::fit::detail::levenberg_marquardt(exp_problem(x, y), Eigen::Vector2d(1.0, 1.0), 200);
  EXPECT_DOUBLE_EQ(res.x[0], 10.0);
  // With a held at 10 the best decay is shallower than 1.3 (it compensates at large x).
  EXPECT_LT(res.x[1], 1.3);
}

TEST(LevenbergMarquardt, StandardErrorsMatchOrdinaryLeastSquares) {
  // Straight line y = a + b x with noise: OLS standard errors are
  //   se(b) = s / sqrt(Sxx), se(a) = s sqrt(1/n + mean(x)^2 / Sxx), s^2 = SSR / (n - 2).
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.1);
  std::vector<double> x, y;
  const int n = 50;
  for (int i = 0; i < n; ++i) {
    x.push_back(i / 10.0);
    y.push_back(1.0 + 0.5 * x.back() + noise(rng));
  }
  LmProblem p;
  p.m = n;
  p.lo = Eigen::Vector2d(-10, -10);
  p.hi = Eigen::Vector2d(10, 10);
  p.h = Eigen::Vector2d(1e-6, 1e-6);
  p.residual = [&](const Eigen::VectorXd& q, Eigen::VectorXd& r) {
    for (int i = 0; i < n; ++i) r[i] = q[0] + q[1] * x[static_cast<std::size_t>(i)] - y[static_cast<std::size_t>(i)];
  };
  const auto res = skin::fit::detail::levenberg_marquardt(p, Eigen::Vector2d(0, 0), 100);
  const auto se = skin::fit::detail::standard_errors(res.J, res.cost);
  double mx = 0;
  for (double v : x) mx += v / n;
  double sxx = 0;
  for (double v : x) sxx += (v - mx) * (v - mx);
  const double s = std::sqrt(res.cost / (n - 2));
  EXPECT_NEAR(se[1], s / std::sqrt(sxx), 1e-6 * se[1] + 1e-9);
  EXPECT_NEAR(se[0], s * std::sqrt(1.0 / n + mx * mx / sxx), 1e-6 * se[0] + 1e-9);
}

TEST(LevenbergMarquardt, UnidentifiableDirectionGetsInfiniteUncertainty) {
  // r depends on q0 + q1 only: the difference is not identifiable.
  Eigen::MatrixXd J(5, 2);
  J.col(0).setOnes();
  J.col(1).setOnes();
  const auto se = skin::fit::detail::standard_errors(J, 1.0);
  EXPECT_TRUE(std::isinf(se[0]));
  EXPECT_TRUE(std::isinf(se[1]));
}
