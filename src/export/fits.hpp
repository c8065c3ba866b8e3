#pragma once
// The fits the target families share (internal to skin::export): the random walk's (Cycles,
// OpenPBR, Standard Surface), Burley's normalized diffusion (Unreal, Unity) and the sum of
// Gaussians (realtime), each through the target's model as the target implements it (export.hpp:
// burley_profile, chiang_alpha, cycles_alpha); and the surface term's mapping.
#include <array>
#include <vector>

#include "target.hpp"

namespace skin::exporting::detail {

// The surface term: DJ06's Torrance-Sparrow lobe with a Beckmann distribution of RMS slope
// m = roughness, scaled by rho_s = oiliness, Fresnel at eta. Targets with a GGX lobe and a
// "perceptual" roughness r (alpha = r^2) get r = sqrt(m): GGX and Beckmann of equal alpha have
// close widths near the peak (Walter et al. 2007).
double perceptual_roughness(const physics::SkinParameters& p);
double fresnel_f0(double eta);

// Random-walk targets (Cycles, OpenPBR, Standard Surface): albedo A through the target's
// inversion alpha(A), the walk's total R(alpha) (data/random_walk_g0.csv), mean free path d.
struct WalkFit {
  util::Rgb A;         // the target's colour parameter (multiple-scattering albedo)
  util::Rgb alpha;     // single-scattering albedo the target derives from it
  util::Rgb d_mm;      // extinction mean free path 1 / sigma_t [mm]
  util::Rgb R_d;       // the target's diffuse reflectance (colour under uniform white light)
  std::array<std::vector<double>, 3> R;  // its profile [1/mm^2]
  bool clamped = false;
};
// `gain`: the target's reflectance per reflectance of the walk (a lobe it adds, 1 if none).
WalkFit fit_walk(const Reference& ref, double (*alpha_of_A)(double), double gain);
// One texel's fit from a walk fit: colour A, radius parameter radius_per_d x d.
TexelFit walk_texel(const Reference& ref, const WalkFit& w, double radius_per_d);

// Burley targets (Unity HDRP, Unreal): R(r) = A burley(d, r); the colour is A itself.
struct BurleyFit {
  util::Rgb A, d_mm, R_d;
  std::array<std::vector<double>, 3> R;
  bool clamped = false;
};
BurleyFit fit_burley(const Reference& ref);

// Sum of Gaussians: R(r) ~ sum_k w_k G(v_k, r), G(v, r) = exp(-r^2 / 2v) / (2 pi v) (integrates
// to 1 over the plane), variances shared by the channels on a geometric ladder v_k = v_0 q^k,
// weights >= 0 per channel by least squares of 2 pi r R(r) in d(ln r); the ladder (v_0, q) by a
// search minimizing the summed relative L1 error (d'Eon, Luebke & Enderton 2007).
struct Gaussians {
  std::vector<double> v;                 // [mm^2]
  std::array<std::vector<double>, 3> w;  // per channel
  std::array<std::vector<double>, 3> R;  // the fitted profile
  double error = 0;
};
Gaussians fit_gaussians(const Reference& ref, int n);

}  // namespace skin::exporting::detail
