#pragma once
// Stacking layers in the frequency domain (DJ05 section 3, model-notes section 4). Each layer's
// reflectance and transmittance are known in closed form as functions of the 2D frequency k; the
// stack's follow from products (2D convolutions in space) with all inter-reflections summed:
//   R12 = R1 + T1_down R2 T1_up / (1 - R1_up R2),   T12 = T1_down T2 / (1 - R1_up R2),
// where *_up is the layer seen from below (its boundaries swapped), not a reuse of *_down.
#include <iosfwd>
#include <vector>

#include "skin/transport/diffusion.hpp"
#include "skin/physics/layer.hpp"
#include "skin/transport/profile_fwd.hpp"

namespace skin::transport {

// Reflectance and transmittance of a layer or stack at one frequency, from above and from below.
struct Transfer {
  double R_down = 0, T_down = 0;  // light arriving from above
  double R_up = 0, T_up = 0;      // light arriving from below
};
std::ostream& operator<<(std::ostream& os, const Transfer& t);

// Adds `below` under `above` (the adding rule above, applied to both directions).
Transfer add_layers(const Transfer& above, const Transfer& below);

// The multipole model of a whole LayerStack.
class DiffusionStack final : public RadialResponse {
 public:
  // Validates the stack (InputError) and builds each layer with the boundary conditions of its
  // neighbours: at an interface between indices n_inside and n_outside, A = A_boundary(n_inside /
  // n_outside), so an interface between equal indices is matched (A = 1).
  explicit DiffusionStack(const physics::LayerStack& stack);

  Transfer at(double k) const;
  double R_k(double k) const { return at(k).R_down; }
  double R_d() const { return at(0.0).R_down; }  // total diffuse reflectance
  double T_d() const { return at(0.0).T_down; }  // total diffuse transmittance (0 if semi-inf.)

  // The top layer's nearest image pair (its dipole), which carries the singular part of R(r) at
  // r -> 0 and is inverted analytically; R_k - dipole_k is smooth and decays fast in k.
  double dipole_k(double k) const { return down_.front().R_dipole_k(k); }
  double dipole(double r) const { return down_.front().R_dipole(r); }
  double residual_k(double k) const override { return R_k(k) - dipole_k(k); }
  double singular(double r) const override { return dipole(r); }
  double total() const override { return R_d(); }

  const std::vector<DiffusionSlab>& slabs() const { return down_; }
  bool semi_infinite() const { return down_.back().semi_infinite(); }

 private:
  std::vector<DiffusionSlab> down_;  // each layer with its boundaries; transfer_k gives both directions
};

}  // namespace skin::transport
