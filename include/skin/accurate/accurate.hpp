#pragma once
// Accurate transport for layered media, beyond diffusion (docs/accurate-solver.md).
//
// adding_doubling(): total reflectance and transmittance of a plane-parallel stack of
// Henyey-Greenstein layers for a pencil beam at normal incidence, by the adding-doubling method
// (van de Hulst 1980, "Multiple Light Scattering", ch. 5; Prahl 1995, "The adding-doubling
// method", in Welch & van Gemert, "Optical-Thermal Response of Laser-Irradiated Tissue"):
// quadrature over the polar cosine, azimuthal Fourier order 0 (all that totals need), delta-M
// scaled Legendre redistribution (Wiscombe 1977), diamond initialisation of a thin layer,
// doubling to the layer thickness (or to convergence for a semi-infinite layer), and adding of
// layers and of Fresnel boundaries (air above, interfaces between layers of different index, the
// medium below). The phase function is Henyey-Greenstein with anisotropy Layer::g and scattering
// coefficient sigma_s = sigma_s_prime / (1 - g).
// The definitions match the Monte Carlo solver (skin::mc::simulate): R_specular is the Fresnel
// reflectance of the top surface at normal incidence; R_d and T_d are per power that entered
// (divided by 1 - R_specular). T_d includes light transmitted without scattering.
//
// AccurateStack: a radial response (for skin::ProfileSolver) whose total is the adding-doubling
// R_d and whose shape comes from the multipole model, corrected per component (the top layer's
// own reflectance, and the light that came back from below it) so that each component's total is
// the adding-doubling one. Units: mm, 1/mm, k in rad/mm.
#include <iosfwd>

#include "skin/physics/layer.hpp"
#include "skin/physics/profile_fwd.hpp"
#include "skin/physics/stack.hpp"

namespace skin::accurate {

// Quadrature directions per hemisphere in each angular panel when Options says "automatic".
inline constexpr int kDefaultQuadraturePoints = 8;

struct Options {
  // Quadrature directions per hemisphere in each angular panel (the hemisphere is split at the
  // critical angles of the stack's interfaces; an index-matched stack has one panel). 0 =
  // automatic (kDefaultQuadraturePoints). Allowed: 0 or [2, 64].
  int quadrature_points = 0;
};
std::ostream& operator<<(std::ostream& os, const Options& o);

struct Totals {
  double R_specular = 0;  // Fresnel reflectance of the top surface at normal incidence
  double R_d = 0;         // diffuse reflectance per power that entered
  double T_d = 0;         // total transmittance per power that entered (0 if semi-infinite)
};
std::ostream& operator<<(std::ostream& os, const Totals& t);

// Validates the stack (LayerStack::validate) and the options (InputError naming the parameter).
Totals adding_doubling(const LayerStack& stack, const Options& options = {});

// An accurate model of a stack for radial profiles: total() == adding_doubling(stack).R_d.
// R(k) = c_top R_top(k) + c_deep (R_stack(k) - R_top(k)), with R_top the multipole reflectance of
// the top layer alone (over the index of what lies below it) and R_stack the multipole stack;
// c_top = R_top^AD / R_top^multipole, and c_deep makes the total the adding-doubling R_d. The
// singular part is c_top times the top layer's dipole. A one-layer stack has c_deep = c_top.
class AccurateStack final : public RadialResponse {
 public:
  explicit AccurateStack(const LayerStack& stack, const Options& options = {});

  double total() const override { return totals_.R_d; }
  double singular(double r) const override;
  double residual_k(double k) const override;

  double R_d() const { return totals_.R_d; }
  double T_d() const { return totals_.T_d; }
  double R_specular() const { return totals_.R_specular; }
  const Totals& totals() const { return totals_; }
  // The correction factors (1 where diffusion already agrees with transport).
  double c_top() const { return c_top_; }
  double c_deep() const { return c_deep_; }

 private:
  Totals totals_;
  DiffusionStack stack_;  // multipole model of the whole stack (its first slab is the top layer
                          // alone, with the same boundaries)
  double c_top_ = 1, c_deep_ = 1;
};
std::ostream& operator<<(std::ostream& os, const AccurateStack& s);

}  // namespace skin::accurate
