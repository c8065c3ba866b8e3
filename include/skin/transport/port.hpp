#pragma once
// Measurements over a finite area: the light an integrating sphere's sample port collects from a
// radial profile (profile.hpp), for fits of such measurements (fit::forward_model_through_port).
#include <vector>

#include "skin/transport/profile.hpp"

namespace skin::transport {

// Measurement over a finite area (an integrating sphere's sample port): light that enters spread
// evenly over a disc of radius `beam_radius` and leaves the skin farther out than the port's edge
// (radius `port_radius`, concentric) is not collected. port_overlap(a, b, r) is the share of the
// beam's disc whose light, moved by r, still lands inside the port: the area of the two discs'
// lens over the beam's area (b = 0, a pencil beam at the centre: 1 for r < a, else 0).
double port_overlap(double port_radius, double beam_radius, double r);

// The reflectance collected through the port, R_d - 2 pi int R(r) (1 - port_overlap(r)) r dr: the
// lost part integrated on radii spaced evenly in ln r from the port's edge (a - b; a / 10^4 when
// the beam fills the port) to max(60 mm, 20 (a + b)) (at most kMaxRadius), where skin's profiles
// have vanished.
// Throws InputError unless 0 < port_radius <= kMaxRadius / 20 and 0 <= beam_radius <=
// port_radius. Not thread-safe (a ProfileSolver inside): one per thread.
class PortCollection {
 public:
  PortCollection(double port_radius, double beam_radius);
  double port_radius() const { return port_; }
  double beam_radius() const { return beam_; }
  // The collected reflectance of one response (at most its total).
  double collected(const RadialResponse& response);

 private:
  double port_, beam_;
  ProfileSolver solver_;
  std::vector<double> loss_weight_;  // quadrature weight of 2 pi (1 - O(r)) r dr at each radius
};

}  // namespace skin::transport
