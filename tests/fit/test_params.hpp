#pragma once
// Shared by the fit tests: the paper's three fitted parameters, the rest at their defaults.
#include "skin/physics/skin_parameters.hpp"

namespace skin_test {
inline skin::SkinParameters params(double cm, double bm, double ch) {
  skin::SkinParameters p;
  p.melanin = cm;
  p.melanin_blend = bm;
  p.hemoglobin = ch;
  return p;
}
}  // namespace skin_test
