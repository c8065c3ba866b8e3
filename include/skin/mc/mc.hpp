#pragma once
// Monte Carlo photon transport in a plane-parallel stack of layers: the reference against which
// the diffusion models are validated. The method is MCML's (Wang, Jacques & Zheng 1995, "MCML:
// Monte Carlo modeling of light transport in multi-layered tissues", Comput. Methods Programs
// Biomed. 47:131-146): a pencil beam at normal incidence, photon packets with weight, exponential
// steps in optical depth carried across interfaces, absorption by weight (w *= albedo at each
// interaction), Henyey-Greenstein scattering, exact unpolarised Fresnel reflection / refraction at
// every interface (reflect or transmit the whole packet with probability R), and Russian roulette
// below a weight threshold. Units: mm, 1/mm.
//
// Reproducibility: photons are simulated in fixed batches, batch b drawing from its own generator
// stream (seed, b); batch tallies are summed in batch order. The same seed gives bit-identical
// results whatever the number of threads.
#include <cstdint>
#include <iosfwd>
#include <vector>

#include "skin/physics/layer.hpp"
#include "skin/util/progress.hpp"
#include "skin/util/work_estimate.hpp"

namespace skin::mc {

// Where the photons start:
// - pencil: a pencil beam at normal incidence on the top surface (MCML; results per power that
//   entered, i.e. after the specular reflection);
// - diffuse_bottom: a Lambertian point source on the bottom boundary of the last (finite) layer,
//   radiating upwards into it (radiance uniform over the upward hemisphere, so the cosine of the
//   direction is drawn with pdf 2 mu). Results per emitted power; R_d is then the power leaving
//   through the top surface and T_d the power returning down through the bottom boundary: a
//   layer's transfer functions for diffuse light arriving from below.
// - diffuse_top: a Lambertian point source on the top surface radiating downwards into the first
//   layer (cosine-weighted directions inside the medium, no refraction): the entry of a
//   renderer's random-walk subsurface scattering (Cycles, Chiang et al. 2016). Results per power
//   that entered; used to tabulate such renderers' response (skin::exporting, data/random-walk.csv).
enum class Source { pencil, diffuse_bottom, diffuse_top };

struct Options {
  std::uint64_t photons = 100000;  // photon packets entering the medium, >= 1
  std::uint64_t seed = 1;
  int threads = 0;       // 0 = all cores
  double r_max = 10.0;   // outer radius of the radial profile [mm], > 0
  std::size_t bins = 200;  // annular bins of width r_max / bins, >= 1
  // Photons finished of options.photons, after each round of batches (may be empty). Every
  // photon ends: by escaping, by the roulette, or after a bounded number of steps (a nearly
  // non-absorbing medium; its weight is then counted in Result::lost).
  util::ProgressCallback progress;
  Source source = Source::pencil;
  // Exit-radius histograms of both surfaces on logarithmic bins (0 = none): bin 0 is
  // [0, exit_r_min), then exit_bins - 1 bins evenly in log r up to exit_r_max [mm]; exits beyond
  // exit_r_max are counted in the totals only. For transfer functions in the frequency domain
  // (hankel_transform). Allowed: exit_bins 0 or >= 2, 0 < exit_r_min < exit_r_max.
  std::size_t exit_bins = 0;
  double exit_r_min = 1e-3, exit_r_max = 10.0;
};
std::ostream& operator<<(std::ostream& os, const Options& o);
// Memory simulate() takes for its tallies with these options [bytes] (one tally of the radial
// and exit bins per batch of a round, and the total), to check a request before it starts.
double memory_bytes(const Options& o);

struct Result {
  double R_specular = 0;  // Fresnel reflectance of the top surface at normal incidence
  // Diffuse reflectance and transmittance per power that entered (divide by 1 - R_specular to
  // get these from per-incident values), with their standard errors (one sigma).
  // T_d includes the unscattered (ballistic) transmission, as MCML's total transmittance.
  double R_d = 0, R_d_se = 0, T_d = 0, T_d_se = 0;
  double R_d_incident = 0, T_d_incident = 0;  // the same per incident power
  // Weight per power that entered of the packets ended after the longest path allowed (millions
  // of steps): 0 but in (nearly) non-absorbing media, where R_d + T_d falls short of 1 by it.
  double lost = 0;
  std::uint64_t photons = 0;
  double seconds = 0;  // wall time
  // R(r) per power that entered [1/mm^2] averaged over annuli [r_i, r_i + dr] (bin-centred
  // r_mm), and its standard error. Light escaping beyond r_max counts in R_d only.
  std::vector<double> r_mm, R, R_se;
  // With Options::exit_bins: bin edges [mm] (exit_bins + 1) and the power leaving through the
  // top and through the bottom surface in each bin (per power that entered / was emitted).
  std::vector<double> exit_r_edges, top_exit, bottom_exit;
};
std::ostream& operator<<(std::ostream& os, const Result& r);

// Validates the stack and the options (InputError naming the parameter), then runs. Polls
// skin::util::cancel (skin/util/cancel.hpp) at every photon and within long ones: throws Cancelled.
Result simulate(const physics::LayerStack& stack, const Options& options);

// Photons per second per thread of `options` on `stack`: a pilot on the calling thread that
// traces photons until it has used a few hundredths of a second of CPU time (or traced
// options.photons), plus at most one photon's longest path. Validates as simulate() does; polls
// skin::util::cancel.
double photons_per_second(const physics::LayerStack& stack, const Options& options);
// The check before a run, shared by `skin mc` and the Python module: its time from
// photons_per_second() and its memory (memory_bytes()) for "a Monte Carlo run of N photons".
// Throws InputError when refused (skin::util::estimate_work); long_run() when it should be announced.
util::WorkEstimate estimate(const physics::LayerStack& stack, const Options& options);

// The 2D Fourier (Hankel) transform F(k) = sum_i w_i J0(k r_i) of exits histogrammed on
// `edges` (weights `w`, one per bin), each bin's weight spread uniformly over its annulus:
// the annulus mean of J0 is 2 (b J1(k b) - a J1(k a)) / (k (b^2 - a^2)). F(0) = sum w. The error
// against the exact per-photon sum is second order in the bin width (tested). k in rad/mm.
double hankel_transform(const std::vector<double>& edges, const std::vector<double>& w, double k);

}  // namespace skin::mc
