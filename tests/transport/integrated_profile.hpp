// Brute-force integrals of radial profiles, shared by the transport tests.
#pragma once

#include <numbers>
#include <vector>

#include "skin/transport/profile.hpp"

namespace skin::test {

// 2 pi int R(r) r dr over a log grid plus the disc r < r_min, where R is taken flat at R(r_min).
inline double integrate_with_disc(const transport::RadialGrid& radii, const std::vector<double>& R) {
  return transport::integrate_profile(radii, R) + std::numbers::pi * radii.r.front() * radii.r.front() * R.front();
}

// The profile a user gets (the response inverted by the ProfileSolver) integrated by brute force
// on a log grid from 1 um to 60 mm (that of Profile.SkinProfilesIntegrateBackToTotal, good to
// 0.5 % for skin: the red tail, sigma_tr ~ 0.4/mm, is inside it, and the 1/r growth towards the
// entry point of dark skin is resolved).
inline double integrated_profile(const transport::RadialResponse& response) {
  static const transport::RadialGrid radii = transport::RadialGrid::logarithmic(1e-6, 60.0, 2400);
  static transport::ProfileSolver solver(radii);  // caches per grid; the tests run on one thread
  return integrate_with_disc(radii, solver.profile(response));
}

}  // namespace skin::test
