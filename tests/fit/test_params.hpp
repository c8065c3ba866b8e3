#pragma once
// Shared by the fit tests: the paper's three fitted parameters, the rest at their defaults, and
// the paper's forward model (the multipole; the library's default is the registry's).
#include "skin/fit/color_fit.hpp"
#include "skin/fit/fit.hpp"
#include "skin/physics/skin_parameters.hpp"

namespace skin_test {
inline skin::physics::SkinParameters params(double cm, double bm, double ch) {
  skin::physics::SkinParameters p;
  p.melanin = cm;
  p.melanin_blend = bm;
  p.hemoglobin = ch;
  return p;
}
inline skin::fit::ForwardModel multipole() { return skin::fit::forward_model("multipole"); }
inline skin::fit::SpectrumFitOptions multipole_spectrum_options() {
  skin::fit::SpectrumFitOptions o;
  o.model = multipole();
  return o;
}
inline skin::fit::ColorFitOptions multipole_color_options() {
  skin::fit::ColorFitOptions o;
  o.model = multipole();
  return o;
}
}  // namespace skin_test
