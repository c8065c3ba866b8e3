#pragma once
// Diffusion theory for one layer: the dipole (semi-infinite, Jensen et al. 2001) and the
// multipole (finite slab, Donner & Jensen 2005, "DJ05"), in space and in the 2D frequency domain.
// Lengths in mm, coefficients in 1/mm, frequencies k in rad/mm, profiles R(r), T(r) in 1/mm^2.
//
// Fourier convention (radially symmetric functions): F(k) = 2 pi int_0^inf f(r) J0(k r) r dr, so
// that F(0) is the total (R_d, T_d) and a 2D convolution is a product.
#include <array>
#include <iosfwd>

namespace skin::transport {

// Diffuse Fresnel reflectance F_dr(eta) for light inside a medium of relative index
// eta = n_inside / n_outside: the polynomial fits used by the multipole papers (Egan & Hilgeman
// 1979 for eta >= 1, its counterpart for eta < 1). F_dr(1) is ~0 (the fit gives 0.0017 there, set
// to exactly 0 for index-matched boundaries).
double F_dr(double eta);
// The same quantity from the exact hemispherical integral of the unpolarised Fresnel
// reflectance, 2 int_0^1 F(mu) mu dmu (reference for tests and for transport solvers).
double F_dr_exact(double eta);
// Boundary mismatch A = (1 + F_dr) / (1 - F_dr); 1 for a matched boundary.
double A_boundary(double eta);

// One layer's diffusion constants with its two boundaries. Built by make(); `flipped()` is the
// same layer seen from below (top and bottom boundary swapped).
struct DiffusionSlab {
  double sigma_a = 0, sigma_s_prime = 1;  // [1/mm]
  double d = 0;                           // thickness [mm], infinity for semi-infinite
  double A_top = 1, A_bottom = 1;
  // Derived (DJ05 section 2): sigma_t' = sigma_a + sigma_s', alpha' = sigma_s' / sigma_t',
  // D = 1 / (3 sigma_t'), sigma_tr = sqrt(sigma_a / D), z_r = 1 / sigma_t', z_b = 2 A D.
  double sigma_t_prime = 1, alpha_prime = 1, D = 1.0 / 3, sigma_tr = 0, z_r = 1;
  double z_b_top = 0, z_b_bottom = 0;
  double L = 0;  // distance between the extrapolated boundaries, d + z_b_top + z_b_bottom

  static DiffusionSlab make(double sigma_a, double sigma_s_prime, double d, double A_top,
                            double A_bottom);
  bool semi_infinite() const;
  DiffusionSlab flipped() const;

  // Frequency domain, exact: the infinite image sums are geometric series in exp(-2 L s),
  // s = sqrt(sigma_tr^2 + k^2), summed in closed form (no truncation at all).
  double R_k(double k) const;
  double T_k(double k) const;  // 0 for a semi-infinite layer
  // R_k and T_k of the slab seen from above and from below (flipped()) at once: the four share
  // sigma_tr, L and two of their six image families, so this costs about a quarter of four calls.
  // Returns {R_down, T_down, R_up, T_up}.
  std::array<double, 4> transfer_k(double k) const;
  double R_d() const { return R_k(0.0); }
  double T_d() const { return T_k(0.0); }

  // Frequency domain by the explicit image sum i = -n..n, stopping when a pair changes the sum by
  // less than tol (relative to the sum) or at max_pairs. For tests of the closed form.
  double R_k_sum(double k, double tol = 1e-12, int max_pairs = 1000000) const;
  double T_k_sum(double k, double tol = 1e-12, int max_pairs = 1000000) const;

  // Space domain [1/mm^2] (DJ05 eqs 8-9), image pairs added until a pair changes the sum by less
  // than tol relative to it (thin, weakly absorbing slabs need many pairs).
  double R(double r, double tol = 1e-10) const;
  double T(double r, double tol = 1e-10) const;

  // The nearest image pair alone (real source at z_r, image at -(z_r + 2 z_b_top)): the dipole of
  // the same medium if it were semi-infinite. It holds the whole singular part of R near r = 0.
  double R_dipole(double r) const;
  double R_dipole_k(double k) const;
};

std::ostream& operator<<(std::ostream& os, const DiffusionSlab& s);

// Closed-form total diffuse reflectance of a semi-infinite medium (Jensen et al. 2001):
// (alpha'/2) (1 + exp(-(4/3) A sqrt(3 (1 - alpha')))) exp(-sqrt(3 (1 - alpha'))).
double R_d_semi_infinite(double alpha_prime, double A);

}  // namespace skin::transport
