#pragma once
// Quadrature rules on [-1, 1] (nodes ascending), computed once per size and cached (thread-safe;
// the returned references stay valid for the program's life).
#include <vector>

namespace skin::util {

struct QuadratureRule {
  std::vector<double> x, w;  // nodes ascending, weights
};

// Gauss-Legendre with n >= 1 nodes: exact for polynomials of degree <= 2n - 1.
const QuadratureRule& gauss_legendre(int n);
// Gauss-Radau with n >= 1 nodes, the last fixed at exactly +1: exact to degree 2n - 2; the fixed
// node's weight is 2 / n^2.
const QuadratureRule& gauss_radau(int n);

}  // namespace skin::util
