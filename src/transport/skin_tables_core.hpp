#pragma once
// What the skin table (skin_stack_table.cpp) and the half-space table (half_space_table.cpp)
// share: how a node is solved and stored as ln rho, and the bounds a parsed table's values keep.
// Internal to skin_transport.
#include <string>
#include <vector>

#include "skin/physics/layer.hpp"

namespace skin::transport::accurate::tables {

// A node's values are floored at kFloor of its peak.
inline constexpr double kFloor = 1e-13;
// A table's ln rho (rho in units of s^2) lies within kMaxLnRho of 0 (the built-in tables' within
// -31.9 and 2.8), and each row within -ln kFloor = 29.93 of its own peak: parse() refuses other
// values. Interpolated values are clamped to kMaxLnRho + kOvershoot, so that exp() of them is
// finite whatever the weights (4-point Lagrange weights grow without bound on nodes nearly
// together): a table that parses gives a finite, non-negative profile by construction. Neither
// bound is reached by interpolation between real nodes (an overshoot of 30 e-folds is not a
// smooth profile's).
inline constexpr double kMaxLnRho = 100, kOvershoot = 30, kMaxRowSpan = 29.94;
double clamp_ln(double v);
// ln R, floored at kFloor of its peak (the tables' values).
std::vector<double> floored_log(std::vector<double> R);
// rho at the x nodes of air over a layer of index eta, g, reduced scattering 1, absorption a_v
// and thickness tau_v (kInfinity: a half-space) over `below` (none: nothing), by FrequencyStack
// in units of s with k0 = 0.3 / 15 (skin_stack_table.cpp).
std::vector<double> solve(const std::vector<double>& x, double eta, double g, double tau_v, double a_v,
                          const physics::Layer* below);
// v with f applied to each value (the interpolation variables: sqrt a, ln tau, ...).
std::vector<double> mapped(const std::vector<double>& v, double (*f)(double));
double log_of(double v);
double sqrt_of(double v);
// A parsed table's x nodes: an odd number evenly spaced in ln x (Simpson's rule and the cubic in
// ln x need them), else InputError naming `source`.
void check_x_nodes(const std::vector<double>& x, const std::string& source);
// A parsed row of ln rho (n values; `row_number` from 1, `columns` its names from the fourth on):
// each within kMaxLnRho of 0 and the row within kMaxRowSpan, else InputError naming `source`.
void check_row(const double* row, std::size_t n, const std::string& source, std::size_t row_number,
               const std::vector<std::string>& columns);
// Node values equal to a relative 1e-6 (a table read back holds 7 digits).
bool same_node(double a, double b);
bool same_nodes(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace skin::transport::accurate::tables
