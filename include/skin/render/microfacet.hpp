#pragma once
// The surface term of the skin BRDF (DJ06 eq 1; model-notes section 5): a Torrance-Sparrow
// microfacet lobe with the Beckmann distribution of RMS slope sigma (0.35 for skin), dielectric
// Fresnel for n = 1.4 and the Cook-Torrance shadowing-masking term, scaled by rho_s. Directions
// are in the local shading frame (normal = +z) and point away from the surface.
#include <iosfwd>
#include <vector>

#include "skin/render/math.hpp"
#include "skin/render/sampling.hpp"

namespace skin::render {

// Beckmann distribution of microfacet normals, normalised so that int D(h) cos(theta_h) dh = 1.
//   D(h) = exp(-tan^2(theta_h) / sigma^2) / (pi sigma^2 cos^4(theta_h))
struct Beckmann {
  double sigma = 0.35;  // RMS slope
  double D(const Vec3& h) const;
  // h distributed as D(h) cos(theta_h): tan^2(theta_h) = -sigma^2 ln(1 - u.x), phi = 2 pi u.y.
  Vec3 sample_h(Vec2 u) const;
  double pdf_h(const Vec3& h) const { return h.z > 0 ? D(h) * h.z : 0.0; }
  Vec2 invert_h(const Vec3& h) const;
};
std::ostream& operator<<(std::ostream& os, const Beckmann& b);

// Cook-Torrance shadowing and masking (Cook & Torrance 1982):
//   G = min(1, 2 (n.h)(n.wo) / (wo.h), 2 (n.h)(n.wi) / (wo.h)).
double cook_torrance_G(const Vec3& wo, const Vec3& wi, const Vec3& h);

class TorranceSparrow {
 public:
  TorranceSparrow(double rho_s, double sigma, double eta);
  // f_s(wo, wi) = rho_s D(h) G F(wi.h) / (4 cos_i cos_o) [1/sr]; 0 unless both above the surface.
  double f(const Vec3& wo, const Vec3& wi) const;
  // Samples wi by reflecting wo about h ~ D(h) cos(theta_h); returns false below the horizon.
  bool sample(const Vec3& wo, Vec2 u, Vec3* wi, double* pdf) const;
  // Solid-angle density of `sample`: D(h) cos(theta_h) / (4 |wo.h|).
  double pdf(const Vec3& wo, const Vec3& wi) const;
  double rho_s() const { return rho_s_; }
  const Beckmann& distribution() const { return beckmann_; }

 private:
  double rho_s_;
  Beckmann beckmann_;
  double eta_;
};

// rho_dr(theta) = int f_s(wo, wi) cos(theta_i) dwi (DJ06 eq 2) for rho_s = 1, tabulated once in
// cos(theta) (scale by rho_s: f_s is linear in it), and its cosine-weighted hemispherical mean
//   rho_dr_mean = 2 int_0^1 rho_dr(mu) mu dmu,
// the fraction of uniform (diffuse) illumination the surface term reflects.
class SpecularAlbedo {
 public:
  SpecularAlbedo(double sigma, double eta, int n_cos = 64);
  double rho_dr(double cos_theta) const;  // linear interpolation in cos(theta)
  double mean() const { return mean_; }

 private:
  std::vector<double> table_;
  double mean_ = 0;
};

}  // namespace skin::render
