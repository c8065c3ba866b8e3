#pragma once
// The frequency-domain profiles of absorbing half-spaces of any g and index of the skin domain,
// tabulated (docs/accurate-solver.md, sec. 4): what the accurate model reads where a top layer
// hides the rest of its stack (AccurateStack::hides_below: a dark epidermis in violet and blue
// light), where it nearly hides the layer below (AccurateStack::nearly_hides_below: both layers'
// half-spaces) and for a lone half-space of such a medium.
//
// Geometry: air over a half-space of index eta, Henyey-Greenstein g, reduced scattering s and
// absorption sigma_a. In units of 1 / s it has one parameter besides g and eta, a = sigma_a / s,
// and its profile is R(r) = s^2 rho(x), x = r s (exactly: a half-space has no length of its own).
// Each node holds ln rho at the x nodes of the skin table (SkinStackTable), computed by
// FrequencyStack as the skin table's nodes are (in units of s, k0 = 0.3 / 15) and floored at
// 1e-13 of its peak. Interpolation: 4-point Lagrange in sqrt a (the skin table's top layer's
// variable), in ln(1 - g) and in eta, then cubic in ln x, with the skin table's continuation below
// the first and beyond the last x node, and scaled to the stack's adding-doubling R_d
// (SkinStackProfile).
#include <string>
#include <string_view>
#include <vector>

#include "skin/physics/layer.hpp"
#include "skin/util/progress.hpp"

namespace skin::transport::accurate {

struct HalfSpaceTable {
  std::string provenance;
  std::vector<double> a, g, eta, x;  // nodes, increasing
  std::vector<double> ln_rho;        // [((i_g * eta.size() + i_eta) * a.size() + i_a) * x.size() + i_x]

  // The built-in nodes (data/half_space_profiles.csv), without values.
  static HalfSpaceTable default_nodes();
  // Computes every node with FrequencyStack (parallel over nodes; cancellable: throws Cancelled).
  // With `reuse` (a table on the same x nodes), the nodes it holds are copied instead of solved.
  void compute(const util::ProgressCallback& progress = {}, const HalfSpaceTable* reuse = nullptr);
  std::string to_csv() const;
  // Throws InputError naming `source` for a malformed table.
  static HalfSpaceTable parse(std::string_view text, std::string_view source);
  static const HalfSpaceTable& builtin();

  // Why the half-space (a, g, eta) under air is not in the table (empty when it is).
  std::string gap(double a_v, double g_v, double eta_v) const;
  // The half-space that stands for `stack` (the top layer of a stack that hides the rest, or a
  // lone half-space) under air, or why there is none in the table (empty when there is); for a
  // top layer that nearly hides a lower half-space, both layers' media must be in the table.
  std::string gap(const physics::LayerStack& stack) const;
  // ln rho at the x nodes (inside the nodes' ranges).
  std::vector<double> ln_rho_at(double a_v, double g_v, double eta_v) const;
  // ln rho of one half-space computed by FrequencyStack, floored as in the table.
  std::vector<double> solve(double a_v, double g_v, double eta_v) const;
};

}  // namespace skin::transport::accurate
