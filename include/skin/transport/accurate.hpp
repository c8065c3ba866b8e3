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
// FrequencyStack: the radial profile of any stack by radiative transfer in the spatial-frequency
// domain, integrating to the adding-doubling R_d. AccurateStack: the same profile, read from the
// table of skin profiles (skin_stack_table.hpp) where it covers the stack, solved elsewhere.
// Units: mm, 1/mm, k in rad/mm.
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "skin/physics/layer.hpp"
#include "skin/transport/profile_fwd.hpp"
#include "skin/transport/model.hpp"
#include "skin/transport/stack.hpp"

namespace skin::transport::accurate {

class SkinStackProfile;  // skin_stack_table.hpp

// Quadrature directions per hemisphere in each angular panel when Options says "automatic":
// kDefaultQuadraturePoints when every layer has the same index (skin), kIndexStepQuadraturePoints
// when layers differ in index (each internal index step adds panels whose radiance needs more
// directions: 8 points left R_d or T_d off by up to 18 %, 16 by up to 1.1 % against 48;
// docs/accurate-solver.md, sec. 2), kForwardQuadraturePoints when a layer scatters more forward
// than g = kForwardG (at g = 0.95 the frequency-domain profile of african skin at 650 nm
// oscillated beyond 0.45 mm with 8, +30 % against Monte Carlo at 0.5-0.55 mm; 10, 12 and 16
// agree within 1 %; R_d moved by 0.6 %). The totals of such a stack get
// kForwardTotalsQuadraturePoints: over the skin domain (skin validate --domain 60) two dark cases
// with g = 0.97 and index 1.33 had R_d 4.3 and 2.9 % below 48 points with 12 (-5.6 and -4.6
// standard errors against Monte Carlo; 1.1-1.7 % at g = 0.95, 0.6 % at 0.93), within 0.1 % with
// 16; the frequency-domain profile keeps 12 (its shape; it is scaled to the totals' R_d) up to g =
// kStrongForwardG, beyond it 16 as well: in the darker of those cases (epidermis 51 um, sigma_a
// 166 /mm, g 0.97, 380 nm) the profile with 12 was +21 % against Monte Carlo at 0.02-0.04 mm and
// 3x the 24-point profile at 0.035 mm; 16 is within 3 % of 24 at 0.025-0.035 mm.
inline constexpr double kStrongForwardG = 0.95;
inline constexpr int kDefaultQuadraturePoints = 8;
inline constexpr int kIndexStepQuadraturePoints = 16;
inline constexpr int kForwardQuadraturePoints = 12;
inline constexpr int kForwardTotalsQuadraturePoints = 16;
inline constexpr double kForwardG = 0.9;

struct Options {
  // Quadrature directions per hemisphere in each angular panel (the hemisphere is split at the
  // critical angles of the stack's interfaces; an index-matched stack has one panel). 0 =
  // automatic (kDefaultQuadraturePoints, kIndexStepQuadraturePoints for stacks whose layers
  // differ in index, for a layer with g > kForwardG kForwardTotalsQuadraturePoints for the
  // totals and kForwardQuadraturePoints for the frequency-domain profile). Allowed: 0 or
  // [2, 64].
  int quadrature_points = 0;
};
std::ostream& operator<<(std::ostream& os, const Options& o);

using Totals = transport::Totals;

// What the adding-doubling solver keeps between stacks: per geometry (stream set, index, g) the
// angular data and the tables of semi-infinite and finite layers over albedo and optical depth,
// filled node by node on demand (a spectrum touches a few hundred nodes; later spectra of
// nearby parameters reuse them: a warm table costs two 4 x 4 weighted sums of matrices instead
// of ~10 doublings). Shared by every thread that uses it (thread-safe). The results do not
// depend on what it already holds (each node is the same whoever fills it). The registry's
// accurate model (skin/transport/model.hpp) holds one.
class Cache {
 public:
  Cache();
  ~Cache();
  Cache(const Cache&) = delete;
  Cache& operator=(const Cache&) = delete;
  struct Impl;  // opaque (src/transport/adding_doubling.cpp)
  Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

// Validates the stack (LayerStack::validate) and the options (InputError naming the parameter).
Totals adding_doubling(const physics::LayerStack& stack, const Options& options, const Cache& cache);
// With a cache of its own (the same numbers; each call fills the table nodes it needs).
Totals adding_doubling(const physics::LayerStack& stack, const Options& options = {});

// Radiative transfer in the spatial-frequency domain (docs/accurate-solver.md, sec. 3): R(k), the
// 2D Fourier transform of the radial profile R(r) of the flux that leaves through the top surface
// (per power that entered, as R_d), for a pencil beam at normal incidence, at each k [rad/mm]
// (>= 0). The same streams, delta-M phase function, layers and interfaces as adding_doubling();
// the azimuthal dependence of the radiance is expanded in cos(a phi), a = 0..azimuthal_orders-1.
// R(0) is adding_doubling()'s R_d computed without its tables (they agree to ~1e-6).
struct FrequencyOptions {
  Options totals;            // quadrature points (as for the totals)
  // Orders at k > 0: 0 = automatic (the same number at every k > 0, more for a thin stack;
  // docs/accurate-solver.md, sec. 3), else [1, 64]. Two stacks that get the same orders compute
  // the same top layers with the same arithmetic (SkinStackTable's light from below).
  int azimuthal_orders = 0;
  // The closed-form single scattering (FrequencyStack) in every layer (true) or in the top layer
  // only (false: the solver of issue 15's first sessions, kept for comparison).
  bool deep_single_scattering = true;
};
std::vector<double> frequency_response(const physics::LayerStack& stack, const std::vector<double>& k,
                                       const FrequencyOptions& options = {});

// The radial response of any stack from frequency_response() (docs/accurate-solver.md, sec. 3):
// R(k) is computed at nodes k_j = k0 sinh(j du) up to k_hi (a multiple of the largest delta-M
// scaled extinction of the stack's layers or inverse layer thickness). The singular part is the light scattered once in
// every layer, exactly (Henyey-Greenstein phase function, Fresnel transmission at every
// interface on the way up), in space (the top layer's 1/r near the beam; evaluated at r >= 1e-6 /
// sigma_t of the top layer); the remainder is R(k) minus the solver's own single scattering (delta-M, discrete), interpolated between the nodes
// (6-point Lagrange in u = asinh(k / k0), so that its error does not echo in the far field), zero
// beyond k_hi (its tail, ~1/k^2, is the pair A (k^2 + b^2)^-q <-> a K_(q-1), matching the rest's
// value and slope at k_hi, so that the remainder ends smoothly instead of ringing), and scaled so
// that the profile integrates to adding_doubling()'s R_d. Light that comes back along the beam
// unscattered (reflected by a slab's bottom or an index step) is a delta at r = 0, drawn as a
// Gaussian of the fixed width kBallisticWidth (2 um; docs/accurate-solver.md, sec. 3).
struct FrequencyProfileOptions {
  FrequencyOptions transport;
  double k_hi = 6;   // top node, in units of the largest delta-M extinction or 1 / thickness
  double du = 0.125;  // node spacing in u
  double k0 = 0.3;   // [rad/mm]
};
class FrequencyStack final : public RadialResponse {
 public:
  explicit FrequencyStack(const physics::LayerStack& stack, const FrequencyProfileOptions& options = {});
  FrequencyStack(const physics::LayerStack& stack, const FrequencyProfileOptions& options,
                 const Cache& cache);
  double total() const override { return totals_.R_d; }
  double singular(double r) const override;
  double residual_k(double k) const override;
  const Totals& totals() const { return totals_; }
  // The nodes and the solver's R(k) there (its R(0) is the untabulated total).
  const std::vector<double>& k_nodes() const { return k_; }
  const std::vector<double>& R_nodes() const { return R_; }
  // Single scattering in every layer (refracted up through the layers above), exactly: in space
  // [1/mm^2], and its total.
  double single_scattering(double r) const;
  double single_scattering_total() const;
  // Light back along the beam without scattering (a delta at r = 0 of this weight, per power
  // that entered; part of total()), and the width [mm] of the Gaussian exp(-r^2 / w^2) / (pi w^2)
  // that stands for the delta in singular(): independent of the stack and narrow against the
  // 10-20 um of the first annuli of a measurement (at 10 um it is e^-25 of its peak), yet wide
  // enough for the project's radial grids, which start at 1 um (r = 0 or the disc below taken
  // flat, then log-spaced: they integrate 97 % of it).
  double ballistic_return() const { return B_; }
  static constexpr double kBallisticWidth = 2e-3;  // [mm]

 private:
  Totals totals_;
  double k0_ = 0.3, du_ = 0.125;
  std::vector<double> k_, R_, G_;  // nodes, R(k_j), remainder at k_j
  double sigma_s_ = 0, sigma_t_ = 1, g_ = 0, d_ = 0, n_ = 1, n_above_ = 1, mu_c_ = 0;
  double r_floor_ = 0;
  // Every layer, top first, for the single scattering below the top layer: scattering and
  // extinction [1/mm] (not delta-M scaled), g, index, thickness [mm], and the beam's weight at its
  // top (attenuated and transmitted at normal incidence by the layers and interfaces above).
  struct ExactLayer {
    double sigma_s = 0, sigma_t = 1, g = 0, n = 1, d = 0, beam = 1;
  };
  std::vector<ExactLayer> layers_;
  bool deep_ = true;
  double escaping_invariant(std::size_t l) const;
  double climb(std::size_t l, double s, double mu) const;
  double deep_single_scattering(std::size_t l, double r) const;
  double deep_single_scattering_total(std::size_t l) const;
  // The rest's tail beyond k_hi: A (k^2 + b^2)^-q, in space tail(r).
  double A_ = 0, b_ = 1, q_ = 1, tail_norm_ = 0;
  static constexpr double kTailExponentMin = 0.25, kTailExponentMax = 2.4;
  double tail(double r) const;
  double B_ = 0;  // light back along the beam unscattered (a Gaussian of width kBallisticWidth)
};

// An accurate model of a stack for radial profiles: total() == adding_doubling(stack).R_d, and
// the profile integrates to it exactly. Two routes to one profile (docs/accurate-solver.md,
// sec. 3-5):
// - the two-layer skin geometry inside the built-in SkinStackTable (skin_stack_table.hpp: the
//   default g, index and dermis scattering, every preset at 380-780 nm): FrequencyStack's
//   profile, tabulated over the stack's three reduced parameters and interpolated (read, not
//   solved; within 0.1-0.4 % of the solver on light skin, a few per cent on the darkest);
// - a half-space, or a stack whose top layer hides what lies below it (hides_below), of g
//   0.7-0.97, index 1.33-1.55 and sigma_a / sigma_s' 0.0625-42.25 under air: the half-space's
//   profile read from the built-in HalfSpaceTable (half_space_table.hpp; FrequencyStack's,
//   tabulated); a top layer over a half-space that nearly hides it (nearly_hides_below): the
//   sum of the two layers' half-spaces, both read from that table;
// - every other stack: FrequencyStack, solved (its cost: docs/benchmarks.md); a stack whose top
//   layer hides what lies below it as that layer's half-space, ~2.4 times faster.
class AccurateStack final : public RadialResponse {
 public:
  explicit AccurateStack(const physics::LayerStack& stack, const Options& options = {});
  // With the solver's cache (the model of the registry keeps one).
  AccurateStack(const physics::LayerStack& stack, const Options& options, const Cache& cache);
  ~AccurateStack() override;

  double total() const override { return totals_.R_d; }
  double singular(double r) const override;
  double residual_k(double k) const override;

  double R_d() const { return totals_.R_d; }
  double T_d() const { return totals_.T_d; }
  double R_specular() const { return totals_.R_specular; }
  const Totals& totals() const { return totals_; }
  // True when the profile is read from a table, the built-in SkinStackTable or HalfSpaceTable
  // (FrequencyStack's, tabulated; otherwise it is solved).
  bool skin_table() const { return skin_ != nullptr; }
  // True when it is read from the HalfSpaceTable.
  bool half_space_table() const { return half_space_table_; }
  // Whether AccurateStack(stack) reads a table: the skin table, or failing it the half-space
  // table (the one routing rule; the model registry asks it before building a response).
  static bool reads_table(const physics::LayerStack& stack);
  static bool reads_skin_table(const physics::LayerStack& stack);
  static bool reads_half_space_table(const physics::LayerStack& stack);
  // Whether the top layer of a stack of two or more layers hides the rest: light that reaches
  // its bottom and returns is attenuated by at least kHiddenBelowEfolds e-folds each way, by the
  // smaller of (sigma_s' + sigma_a) d (the straight path) and sqrt(3 sigma_a (sigma_s' +
  // sigma_a)) d (diffusion). Its profile is then solved as the top layer's half-space (the
  // totals stay the whole stack's). Measured against the whole stack solved (2026-12-07, ten
  // skin stacks with a dark epidermis): within 1.4e-5 above 1e-4 of the peak and 7.5e-4 above
  // 1e-6 at 10.3 e-folds; 6 % above 1e-6 at 7.2 (docs/accurate-solver.md sec. 5).
  static bool hides_below(const physics::LayerStack& stack);
  static constexpr double kHiddenBelowEfolds = 10.0;
  // Whether the top layer of two (a finite layer over a half-space) nearly hides the lower one:
  // kNearlyHiddenEfolds up to kHiddenBelowEfolds e-folds each way, counted as in hides_below.
  // Its profile is then the top layer's half-space plus what the lower layer returns (the
  // stack's R_d less the top half-space's, when positive) spread as the lower layer's own
  // half-space, both read from the HalfSpaceTable (docs/accurate-solver.md sec. 5); a negative
  // remainder (a lower layer that returns less than the top layer's medium would) leaves the top
  // half-space alone, scaled to the stack's R_d. Measured against the whole stack solved
  // (2026-12-08, skin stacks of the domain's sample, seed 7): 20 with 7-10 e-folds within 0.07 %
  // where R is above 1e-4 of R(0.02 mm) and 4.5 % above 1e-6; 30 with 6-7 within 3.7 % and 33 %,
  // 20 with 5.5-6 within 9.7 % and 45 % (all low: the lower layer's light spreads wider through
  // the top than its half-space's), hence the limit 7 (docs/accurate-solver.md sec. 5).
  static bool nearly_hides_below(const physics::LayerStack& stack);
  static constexpr double kNearlyHiddenEfolds = 7.0;
  // The e-folds of hides_below: the smaller of the straight and the diffusive attenuation across
  // the top layer of a stack of two or more layers (0 for one layer or a top without a finite
  // thickness).
  static double top_layer_efolds(const physics::LayerStack& stack);
  // True when the profile is the top layer's half-space (hides_below), read or solved, or that
  // half-space with the lower layer's added (nearly_hides_below; then below_as_half_space()).
  bool top_as_half_space() const { return top_as_half_space_; }
  bool below_as_half_space() const { return below_ != nullptr; }

 private:
  Totals totals_;
  std::unique_ptr<FrequencyStack> frequency_;  // set outside the skin table
  std::unique_ptr<SkinStackProfile> skin_;     // set for the skin geometry
  std::unique_ptr<SkinStackProfile> below_;    // what the lower layer returns (nearly_hides_below)
  bool top_as_half_space_ = false, half_space_table_ = false;
};
std::ostream& operator<<(std::ostream& os, const AccurateStack& s);

}  // namespace skin::transport::accurate
