#pragma once
// The response of an index-matched half-space to light entering it diffusely: what a renderer's
// random-walk subsurface scattering computes (Cycles, Arnold, RenderMan after Chiang, Kutz &
// Burley 2016, "Practical and Controllable Subsurface Scattering for Production Path Tracing").
// The walk starts at a surface point with a cosine-weighted direction into the medium, scatters
// with single-scattering albedo alpha and a Henyey-Greenstein phase function, and ends when it
// crosses the surface (no Fresnel: the boundary is index-matched). In units of the mean free
// path 1 / sigma_t the result depends on alpha (and g) alone:
//   R_d(alpha)            the power that leaves through the surface, per power that entered;
//   fraction of it leaving in annuli of rho = sigma_t r.
// Tabulated by Monte Carlo (skin::mc::tabulate_random_walk, `skin tabulate-random-walk`) into
// data/random_walk_g0.csv and interpolated in log(1 - alpha).
#include <iosfwd>
#include <string>
#include <vector>

namespace skin::transport {

class RandomWalkTable {
 public:
  double g = 0.0;                     // Henyey-Greenstein anisotropy of the walk
  std::string provenance;             // how the table was made
  std::vector<double> alpha;          // single-scattering albedo nodes, increasing, in (0, 1)
  std::vector<double> rho_edges;      // annulus edges in rho = sigma_t r, rho_edges[0] = 0
  std::vector<double> R_d;            // per node
  std::vector<double> R_d_se;         // its standard error (one sigma)
  // fraction[i][b]: power leaving in annulus b, per power that entered (sums to <= R_d[i]; the
  // rest left beyond rho_edges.back()).
  std::vector<std::vector<double>> fraction;

  // The built-in table (data/random_walk_g0.csv).
  static const RandomWalkTable& builtin();
  // Parses the CSV written by to_csv(); `source` names it in messages (InputError).
  static RandomWalkTable from_csv(std::string_view text, const std::string& source);
  std::string to_csv() const;

  // Interpolated in x = log(1 - alpha) between nodes; above the last node clamped, below the
  // first scaled linearly to 0 at alpha = 0.
  double reflectance(double alpha) const;
  // Mean exit radius of the reflected light, in mean free paths: int rho R dA / int R dA.
  double mean_rho(double alpha) const;
  // R(rho) per power that entered [per mean free path^2] at the given rho (> 0): each annulus's
  // power spread over its area, interpolated in log rho between annulus centres.
  std::vector<double> density(double alpha, const std::vector<double>& rho) const;
  // Fractions per annulus at alpha (interpolated).
  std::vector<double> fractions(double alpha) const;
};

std::ostream& operator<<(std::ostream& os, const RandomWalkTable& t);

}  // namespace skin::transport
