#pragma once
// A radial diffusion profile R(r) [1/mm^2] tabulated on a radial grid, ready for importance
// sampling of the BSSRDF's exit point by radius (King et al. 2013; pbrt-v3 section 15.4).
//
// The table stores f(r) = 2 pi r R(r), the density per unit radius, as piecewise linear between
// the grid radii. Sampling draws r from f+ = max(f, 0) (a diffusion profile weighted into sRGB
// channels can dip below zero where the channel's colour-matching weights are negative), and
// eval() returns the signed profile rescaled so that its integral over the plane equals the exact
// total R_d (from k = 0 of the frequency-domain solution): tabulation and truncation then cost
// no energy, and where R >= 0 the estimator R(r) / pdf(r) is the constant R_d.
#include <iosfwd>
#include <vector>

namespace skin::render {

class TabulatedProfile {
 public:
  TabulatedProfile() = default;
  // radii [mm] increasing from >= 0, R [1/mm^2] at each radius, R_d the exact total. The table is
  // cut at the radius holding all but `tail` of the integral of |f|.
  TabulatedProfile(const std::vector<double>& radii, const std::vector<double>& R, double R_d,
                   double tail = 1e-3);

  // Radius [mm] from u in [0, 1): inverse CDF of f+ within one linear segment (a quadratic).
  double sample_radius(double u) const;
  // Density of sample_radius per unit radius [1/mm], and per unit area [1/mm^2] (= pdf_radius /
  // (2 pi r), finite at r = 0).
  double pdf_radius(double r) const;
  double pdf_area(double r) const;
  // CDF: the u for which sample_radius returns r.
  double invert_radius(double r) const;
  // The rescaled profile R(r) [1/mm^2] (signed); integrates to R_d over the plane.
  double eval(double r) const;

  double r_max() const { return r_.empty() ? 0.0 : r_.back(); }  // [mm]
  double R_d() const { return R_d_; }
  bool empty() const { return r_.empty(); }
  const std::vector<double>& radii() const { return r_; }
  // Integral of f+ over [r_a, r_b] normalised (probability of that radius range, for tests).
  double probability(double r_a, double r_b) const;

 private:
  std::size_t segment(double r) const;
  double f_plus_at(double r) const;
  std::vector<double> r_, f_, f_plus_, cdf_;  // cdf_ of f+, normalised
  double scale_ = 0;      // R_d / integral of signed f
  double total_plus_ = 0; // integral of f+
  double R_d_ = 0;
};
std::ostream& operator<<(std::ostream& os, const TabulatedProfile& p);

}  // namespace skin::render
