// Monte Carlo photon transport in layered media (MCML's method; see mc.hpp for the references).
#include "skin/mc/mc.hpp"

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <boost/random/exponential_distribution.hpp>
#include <chrono>
#include <ctime>
#include <cmath>
#include <limits>
#include <numbers>
#include <ostream>

#include "skin/mc/sampling.hpp"
#include "skin/physics/fresnel.hpp"
#include "skin/util/cancel.hpp"
#include "skin/util/error.hpp"

namespace skin::mc {

using skin::util::InputError;
using skin::util::WorkEstimate;
using skin::util::estimate_work;
using skin::util::require_positive;

using skin::physics::FresnelResult;
using skin::physics::Layer;
using skin::physics::LayerStack;
using skin::physics::fresnel;

namespace {
// Boost.Random's engine interface over the batch generator, for its ziggurat. Boost takes the
// ziggurat layer from the low 8 bits of a draw and the uniform from the rest; xoshiro256+'s
// lowest bits are its weak ones (Blackman & Vigna 2018), so the top 8 bits are rotated down
// there and the weak bits end in the uniform's least significant places.
struct BoostEngine {
  using result_type = std::uint64_t;
  Rng& rng;
  static constexpr result_type min() { return 0; }
  static constexpr result_type max() { return ~result_type{0}; }
  result_type operator()() {
    const std::uint64_t x = rng.next_u64();
    return (x << 8) | (x >> 56);
  }
};

// cos and sin of 2 pi i / 256, for azimuth().
struct AzimuthTable {
  std::array<double, 256> c{}, s{};
  AzimuthTable() {
    for (std::size_t i = 0; i < 256; ++i) {
      const double phi = 2.0 * std::numbers::pi * static_cast<double>(i) / 256.0;
      c[i] = std::cos(phi);
      s[i] = std::sin(phi);
    }
  }
};
const AzimuthTable kAzimuthTable;

// cos and sin of the uniform azimuth phi = 2 pi (i + f) / 256 of 64 random bits: the top 8 bits
// give the sector i, the next 53 the fraction f in [0, 1). cos and sin of the sector's start come
// from the table and those of delta = 2 pi f / 256 < 0.0246 from their Taylor series, to the
// delta^8 and delta^7 terms (truncation below 1e-17), combined by the angle-addition formulas:
// no rejection loop, no division, no branch; within 2e-15 of std::cos / std::sin (tested).
[[gnu::always_inline]] inline Azimuth azimuth_inline(std::uint64_t bits) {
  constexpr double kScale = 2.0 * std::numbers::pi / 256.0 * 0x1.0p-53;
  const auto i = static_cast<std::size_t>(bits >> 56);
  const double d =
      static_cast<double>(static_cast<std::int64_t>((bits >> 3) & ((1ULL << 53) - 1))) * kScale;
  const double d2 = d * d;
  const double cd = 1.0 + d2 * (-1.0 / 2 + d2 * (1.0 / 24 + d2 * (-1.0 / 720 + d2 * (1.0 / 40320))));
  const double sd = d * (1.0 + d2 * (-1.0 / 6 + d2 * (1.0 / 120 + d2 * (-1.0 / 5040))));
  const double c = kAzimuthTable.c[i], s = kAzimuthTable.s[i];
  return {c * cd - s * sd, s * cd + c * sd};
}

// The unit exponential by Boost's ziggurat, inlined into the photon loop.
[[gnu::always_inline]] inline double unit_exponential(Rng& rng) {
  BoostEngine engine{rng};
  return boost::random::exponential_distribution<double>()(engine);
}
}  // namespace

double sample_optical_depth(Rng& rng) { return unit_exponential(rng); }
Azimuth azimuth(std::uint64_t bits) { return azimuth_inline(bits); }

namespace {

// Russian roulette (MCML's choice): below this weight a packet survives with probability
// kSurvival and has its weight divided by it, which keeps the estimate unbiased.
constexpr double kWeightThreshold = 1e-4;
constexpr double kSurvival = 0.1;
// Photons per batch: each batch has its own generator stream and tally, so the batch size (not
// the thread count) fixes the result. Small enough for good load balance on short runs.
constexpr std::uint64_t kBatchPhotons = 1000;
// The longest path: a packet still travelling after this many steps (interactions and boundary
// hits) ends there, its weight counted as lost (Result::lost). With any absorption the roulette
// ends a packet long before (its weight falls below kWeightThreshold after ~9.2 / (1 - albedo)
// interactions); without, in a half-space, a packet ends only by escaping, and the number of
// steps that takes has no finite mean: this bound keeps every photon, the pilot and the run
// finite. In a non-absorbing half-space (g 0.9, eta 1.4) about 1 % of the weight reaches it.
// Cancellation is polled at each photon and every kPollSteps steps within one.
constexpr std::uint64_t kPollSteps = 1 << 16;
constexpr std::uint64_t kMaxSteps = 128 * kPollSteps;  // 8.4 million

// One layer, prepared for the inner loop.
struct Slab {
  double z_top = 0, z_bottom = 0;  // [mm]; z grows downwards, z_bottom = inf if semi-infinite
  double sigma_t = 1;              // sigma_a + sigma_s [1/mm]
  double inv_sigma_t = 1;
  double albedo = 1;               // sigma_s / sigma_t
  HenyeyGreenstein phase;          // the layer's g
  double eta = 1;
  double eta_up = 1, eta_down = 1;  // index across the top and the bottom boundary
};

// Tallies of one batch. A packet leaves the medium at most once (whole-packet Fresnel decisions),
// so per-photon sums of weight and weight^2 give exact sample variances.
struct Tally {
  std::vector<double> S1, S2;  // reflected weight per annulus, and its square
  std::vector<double> E_top, E_bottom;  // exit weight per logarithmic bin (Options::exit_bins)
  double R1 = 0, R2 = 0, T1 = 0, T2 = 0;
  double lost = 0;  // weight of packets ended at kMaxSteps
  explicit Tally(std::size_t bins = 0, std::size_t exit_bins = 0)
      : S1(bins, 0.0), S2(bins, 0.0), E_top(exit_bins, 0.0), E_bottom(exit_bins, 0.0) {}
  void clear() {
    for (auto* v : {&S1, &S2, &E_top, &E_bottom}) std::fill(v->begin(), v->end(), 0.0);
    R1 = R2 = T1 = T2 = 0;
    lost = 0;
  }
  void add(const Tally& o) {
    for (std::size_t i = 0; i < S1.size(); ++i) {
      S1[i] += o.S1[i];
      S2[i] += o.S2[i];
    }
    for (std::size_t i = 0; i < E_top.size(); ++i) {
      E_top[i] += o.E_top[i];
      E_bottom[i] += o.E_bottom[i];
    }
    R1 += o.R1;
    R2 += o.R2;
    T1 += o.T1;
    T2 += o.T2;
    lost += o.lost;
  }
};

// Logarithmic exit-radius bins (Options::exit_bins): bin 0 is [0, r_min), bin i >= 1 covers
// [r_min q^(i-1), r_min q^i), q = (r_max / r_min)^(1 / (n - 1)).
struct ExitBins {
  std::size_t n = 0;
  double r_min = 1, inv_log_q = 1;
  ExitBins() = default;
  ExitBins(std::size_t n_, double r_min_, double r_max)
      : n(n_), r_min(r_min_),
        inv_log_q(n_ > 1 ? static_cast<double>(n_ - 1) / std::log(r_max / r_min_) : 1.0) {}
  // The bin of radius r, or n if beyond r_max.
  std::size_t bin(double r) const {
    if (r < r_min) return 0;
    const double b = 1.0 + std::log(r / r_min) * inv_log_q;
    return b < static_cast<double>(n) ? static_cast<std::size_t>(b) : n;
  }
  std::vector<double> edges() const {
    std::vector<double> e(n + 1, 0.0);
    for (std::size_t i = 1; i <= n; ++i)
      e[i] = r_min * std::exp(static_cast<double>(i - 1) / inv_log_q);
    return e;
  }
};

std::vector<Slab> prepare(const LayerStack& stack) {
  std::vector<Slab> slabs(stack.layers.size());
  double z = 0;
  for (std::size_t i = 0; i < slabs.size(); ++i) {
    const Layer& l = stack.layers[i];
    Slab& s = slabs[i];
    const double sigma_s = l.sigma_s();  // sigma_s' / (1 - g)
    s.z_top = z;
    s.z_bottom = l.semi_infinite() ? std::numeric_limits<double>::infinity() : z + l.thickness;
    z = s.z_bottom;
    s.sigma_t = l.sigma_a + sigma_s;
    s.inv_sigma_t = 1.0 / s.sigma_t;
    s.albedo = sigma_s / s.sigma_t;
    s.phase = HenyeyGreenstein(l.g);
    s.eta = l.eta;
    s.eta_up = i == 0 ? stack.eta_above : stack.layers[i - 1].eta;
    s.eta_down = i + 1 == slabs.size() ? stack.eta_below : stack.layers[i + 1].eta;
  }
  return slabs;
}

// The angles of one scattering: cos(theta) from the phase function of asymmetry g, and
// sin(theta) cos(phi), sin(theta) sin(phi) with a uniform azimuth phi.
struct Turn {
  double cos_t, st_cp, st_sp;
};
[[gnu::always_inline]] inline Turn draw_turn(const HenyeyGreenstein& phase, Rng& rng) {
  const double cos_t = phase.sample_cos(rng.uniform());
  const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
  const Azimuth phi = azimuth_inline(rng.next_u64());
  return {cos_t, sin_t * phi.cos_phi, sin_t * phi.sin_phi};
}

// Traces `count` packets, drawing from `rng`, into `tally`; returns early (the tally then
// incomplete) when cancellation is requested. The generator is a local copy, so that its state
// stays in registers.
void trace(const std::vector<Slab>& slabs, std::uint64_t count, Rng rng, double inv_dr,
           Source source, const ExitBins& exits, Tally& tally) {
  const std::size_t n_layers = slabs.size();
  const std::size_t bins = tally.S1.size();
  for (std::uint64_t p = 0; p < count; ++p) {
    if (util::cancel::requested()) return;
    double x = 0, y = 0, z = 0;
    double ux = 0, uy = 0, uz = 1;  // pencil beam at normal incidence (refraction-free)
    double w = 1;                   // per power that entered
    std::size_t li = 0;
    if (source != Source::pencil) {
      // Lambertian emission into the medium, downwards from the top surface (diffuse_top) or
      // upwards from the bottom boundary (diffuse_bottom): mu = sqrt(u) has pdf 2 mu.
      if (source == Source::diffuse_bottom) {
        li = n_layers - 1;
        z = slabs[li].z_bottom;
      }
      const double mu = std::sqrt(rng.uniform_open0());
      const double sin_t = std::sqrt(std::max(0.0, 1.0 - mu * mu));
      const Azimuth phi = azimuth_inline(rng.next_u64());
      ux = sin_t * phi.cos_phi;
      uy = sin_t * phi.sin_phi;
      uz = source == Source::diffuse_top ? mu : -mu;
    }
    double tau_left = 0;  // unused optical depth carried across an interface
    for (std::uint64_t steps = 1;; ++steps) {
      if (steps % kPollSteps == 0) [[unlikely]] {
        if (steps >= kMaxSteps) {
          tally.lost += w;
          break;
        }
        if (util::cancel::requested()) return;
      }
      const Slab& s = slabs[li];
      const double tau = tau_left > 0 ? tau_left : unit_exponential(rng);
      const double step = tau * s.inv_sigma_t;
      const double z_next = z + uz * step;
      // Most steps end inside the layer: that test needs no division. Otherwise (rarely) the
      // distance to the boundary decides, as in MCML.
      if (!(z_next > s.z_top && z_next < s.z_bottom)) {
        const double to_boundary = uz > 0   ? (s.z_bottom - z) / uz
                                   : uz < 0 ? (s.z_top - z) / uz
                                            : std::numeric_limits<double>::infinity();
        if (step >= to_boundary) {
          // Hit the boundary: move onto it and keep the optical depth not yet used (MCML 3.4).
          x += ux * to_boundary;
          y += uy * to_boundary;
          const bool down = uz > 0;
          z = down ? s.z_bottom : s.z_top;
          tau_left = std::max(0.0, tau - to_boundary * s.sigma_t);
          const double n2 = down ? s.eta_down : s.eta_up;
          if (n2 != s.eta) {
            const FresnelResult f = fresnel(std::abs(uz), s.eta, n2);
            if (f.R >= 1.0 || rng.uniform() < f.R) {  // internal reflection of the whole packet
              uz = -uz;
              continue;
            }
            const double k = s.eta / n2;  // Snell: the tangential component scales by n1/n2
            ux *= k;
            uy *= k;
            uz = down ? f.cos_t : -f.cos_t;
          }
          if (down) {
            if (li + 1 == n_layers) {  // transmitted out of the bottom
              if (exits.n) {
                const std::size_t b = exits.bin(std::sqrt(x * x + y * y));
                if (b < exits.n) tally.E_bottom[b] += w;
              }
              tally.T1 += w;
              tally.T2 += w * w;
              break;
            }
            ++li;
          } else {
            if (li == 0) {  // reflected out of the top
              const double r = std::sqrt(x * x + y * y);
              const double b = r * inv_dr;
              if (b < static_cast<double>(bins)) {
                const auto i = static_cast<std::size_t>(b);
                tally.S1[i] += w;
                tally.S2[i] += w * w;
              }
              if (exits.n) {
                const std::size_t e = exits.bin(r);
                if (e < exits.n) tally.E_top[e] += w;
              }
              tally.R1 += w;
              tally.R2 += w * w;
              break;
            }
            --li;
          }
          continue;
        }
      }
      // Interaction inside the layer: absorb the fraction 1 - albedo, then scatter.
      x += ux * step;
      y += uy * step;
      z = z_next;
      tau_left = 0;
      w *= s.albedo;
      const Turn turn = draw_turn(s.phase, rng);
      scatter_direction(ux, uy, uz, turn.cos_t, turn.st_cp, turn.st_sp);
      if (w < kWeightThreshold) {
        if (rng.uniform() < kSurvival) {
          w /= kSurvival;
        } else {
          break;
        }
      }
    }
  }
}

// Batches per round: enough to keep every thread busy between the ordered sums.
std::uint64_t round_size(int threads) {
  return std::max<std::uint64_t>(64, 16 * static_cast<std::uint64_t>(threads));
}

int thread_count(const Options& o) { return o.threads > 0 ? o.threads : tbb::info::default_concurrency(); }

void validate(const Options& o) {
  if (o.photons < 1) throw InputError("photons = 0 is out of range: must be >= 1");
  if (o.threads < 0)
    throw InputError("threads = " + std::to_string(o.threads) +
                     " is out of range: must be >= 0 (0 = all cores)");
  require_positive("radius-max", o.r_max, "mm");
  if (o.bins < 1 || o.bins > 1000000)
    throw InputError("bins = " + std::to_string(o.bins) + " is out of range: must be in [1, 1e6]");
  if (o.exit_bins == 1 || o.exit_bins > 1000000)
    throw InputError("exit_bins = " + std::to_string(o.exit_bins) +
                     " is out of range: must be 0 or in [2, 1e6]");
  if (o.exit_bins) {
    require_positive("exit_r_min", o.exit_r_min, "mm");
    if (!(o.exit_r_max > o.exit_r_min))
      throw InputError("exit_r_max = " + std::to_string(o.exit_r_max) +
                       " is out of range: must be > exit_r_min");
  }
}

}  // namespace

std::ostream& operator<<(std::ostream& os, const Options& o) {
  return os << "mc::Options{photons=" << o.photons << ", seed=" << o.seed
            << ", threads=" << o.threads << ", r_max=" << o.r_max << "mm, bins=" << o.bins
            << ", progress=" << (o.progress ? "on" : "off") << ", source="
            << (o.source == Source::pencil           ? "pencil"
              : o.source == Source::diffuse_top ? "diffuse_top"
                                                : "diffuse_bottom")
            << ", exit_bins=" << o.exit_bins << " [" << o.exit_r_min << ", " << o.exit_r_max
            << "]mm}";
}

std::ostream& operator<<(std::ostream& os, const Result& r) {
  os << "mc::Result{R_specular=" << r.R_specular << ", R_d=" << r.R_d << " +- " << r.R_d_se
     << ", T_d=" << r.T_d << " +- " << r.T_d_se << ", R_d_incident=" << r.R_d_incident
     << ", T_d_incident=" << r.T_d_incident << ", lost=" << r.lost << ", photons=" << r.photons
     << ", seconds=" << r.seconds << ", bins=" << r.R.size();
  if (!r.R.empty())
    os << ", R(r=" << r.r_mm.front() << "mm)=" << r.R.front() << " +- " << r.R_se.front();
  return os << '}';
}

double photons_per_second(const LayerStack& stack, const Options& options) {
  stack.validate();
  validate(options);
  if (options.source == Source::diffuse_bottom && stack.semi_infinite())
    throw InputError("source = diffuse_bottom needs a finite last layer (it starts on its bottom)");
  const std::vector<Slab> slabs = prepare(stack);
  // CPU time of this thread: the rate is per thread, and a busy machine would inflate wall time.
  const auto cpu_seconds = [] {
    timespec t{};
    ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  };
  constexpr double kPilotSeconds = 0.05;
  const double start = cpu_seconds();
  double seconds = 0;
  std::uint64_t done = 0;
  // Chunks of 1, 2, 4, ... photons, each from its own generator stream (apart from the run's).
  for (std::uint64_t chunk = 1; done < options.photons && seconds < kPilotSeconds; chunk *= 2) {
    const std::uint64_t n = std::min(chunk, options.photons - done);
    Tally t(1, 0);
    trace(slabs, n, Rng(options.seed, ~std::uint64_t{0} - done), 1.0 / options.r_max, options.source,
          ExitBins(), t);
    util::cancel::check();
    done += n;
    seconds = cpu_seconds() - start;
  }
  return static_cast<double>(done) / std::max(seconds, 1e-6);
}

WorkEstimate estimate(const LayerStack& stack, const Options& options) {
  const double rate = photons_per_second(stack, options);
  return estimate_work("a Monte Carlo run of " + std::to_string(options.photons) + " photons",
                       static_cast<double>(options.photons), rate, thread_count(options),
                       memory_bytes(options));
}

double memory_bytes(const Options& o) {
  const std::uint64_t n_batches = (o.photons + kBatchPhotons - 1) / kBatchPhotons;
  const double tallies = static_cast<double>(std::min(round_size(thread_count(o)), n_batches) + 1);
  return tallies * 2.0 * static_cast<double>(o.bins + o.exit_bins) * sizeof(double);
}

Result simulate(const LayerStack& stack, const Options& options) {
  stack.validate();
  validate(options);
  if (options.source == Source::diffuse_bottom && stack.semi_infinite())
    throw InputError("source = diffuse_bottom needs a finite last layer (it starts on its bottom)");
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<Slab> slabs = prepare(stack);
  const std::size_t bins = options.bins;
  const double dr = options.r_max / static_cast<double>(bins);
  const double inv_dr = 1.0 / dr;

  const std::uint64_t N = options.photons;
  const std::uint64_t n_batches = (N + kBatchPhotons - 1) / kBatchPhotons;
  const int threads = thread_count(options);
  tbb::task_arena arena(threads);
  // Batches run in rounds; within a round each batch fills its own tally, and the tallies are
  // then added in batch order, so the floating-point sums do not depend on the schedule.
  const std::uint64_t round = round_size(threads);
  const ExitBins exits = options.exit_bins
                             ? ExitBins(options.exit_bins, options.exit_r_min, options.exit_r_max)
                             : ExitBins();
  std::vector<Tally> slots(static_cast<std::size_t>(std::min(round, n_batches)),
                           Tally(bins, exits.n));
  Tally total(bins, exits.n);
  for (std::uint64_t first = 0; first < n_batches; first += round) {
    const std::uint64_t count = std::min(round, n_batches - first);
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, count, 1),
                        [&](const tbb::blocked_range<std::uint64_t>& range) {
                          for (std::uint64_t k = range.begin(); k != range.end(); ++k) {
                            if (util::cancel::requested()) return;  // thrown below, after the round
                            const std::uint64_t b = first + k;
                            const std::uint64_t photons =
                                std::min(kBatchPhotons, N - b * kBatchPhotons);
                            Tally& t = slots[static_cast<std::size_t>(k)];
                            t.clear();
                            Rng rng(options.seed, b);
                            trace(slabs, photons, rng, inv_dr, options.source, exits, t);
                          }
                        });
    });
    util::cancel::check();
    for (std::uint64_t k = 0; k < count; ++k) total.add(slots[static_cast<std::size_t>(k)]);
    if (options.progress)
      options.progress(static_cast<std::size_t>(std::min(N, (first + count) * kBatchPhotons)),
                       static_cast<std::size_t>(N));
  }

  Result r;
  const double eta0 = stack.layers.front().eta;
  const double q = (stack.eta_above - eta0) / (stack.eta_above + eta0);
  // Fresnel at normal incidence (no beam meets the top surface from outside for diffuse_bottom)
  r.R_specular = options.source == Source::pencil ? q * q : 0.0;
  const double n = static_cast<double>(N);
  // Standard error of a mean of N per-photon contributions X: sqrt((E[X^2] - E[X]^2) / (N - 1)).
  auto se = [n](double s1, double s2) {
    if (n < 2) return 0.0;
    const double m = s1 / n;
    return std::sqrt(std::max(0.0, s2 / n - m * m) / (n - 1.0));
  };
  r.R_d = total.R1 / n;
  r.R_d_se = se(total.R1, total.R2);
  r.T_d = total.T1 / n;
  r.T_d_se = se(total.T1, total.T2);
  r.lost = total.lost / n;
  r.R_d_incident = r.R_d * (1.0 - r.R_specular);
  r.T_d_incident = r.T_d * (1.0 - r.R_specular);
  r.photons = N;
  r.r_mm.resize(bins);
  r.R.resize(bins);
  r.R_se.resize(bins);
  for (std::size_t i = 0; i < bins; ++i) {
    const double ri = static_cast<double>(i);
    r.r_mm[i] = (ri + 0.5) * dr;
    const double area = std::numbers::pi * dr * dr * (2.0 * ri + 1.0);  // pi (r_o^2 - r_i^2)
    r.R[i] = total.S1[i] / n / area;
    r.R_se[i] = se(total.S1[i], total.S2[i]) / area;
  }
  if (exits.n) {
    r.exit_r_edges = exits.edges();
    r.top_exit.resize(exits.n);
    r.bottom_exit.resize(exits.n);
    for (std::size_t i = 0; i < exits.n; ++i) {
      r.top_exit[i] = total.E_top[i] / n;
      r.bottom_exit[i] = total.E_bottom[i] / n;
    }
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

double hankel_transform(const std::vector<double>& edges, const std::vector<double>& w, double k) {
  double F = 0;
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (w[i] == 0.0) continue;
    const double a = edges[i], b = edges[i + 1];
    if (k * b < 1e-3) {  // J0 ~ 1 - (k r)^2 / 4: annulus mean 1 - k^2 (a^2 + b^2) / 8
      F += w[i] * (1.0 - k * k * (a * a + b * b) / 8.0);
      continue;
    }
    const double Ja = a > 0 ? a * std::cyl_bessel_j(1.0, k * a) : 0.0;
    F += w[i] * 2.0 * (b * std::cyl_bessel_j(1.0, k * b) - Ja) / (k * (b * b - a * a));
  }
  return F;
}

double hg_pdf_cos(double g, double mu) {
  const double d = 1.0 + g * g - 2.0 * g * mu;
  return 0.5 * (1.0 - g * g) / (d * std::sqrt(d));
}

double hg_invert_cos(double g, double mu) {
  if (std::abs(g) < 1e-6) return 0.5 * (mu + 1.0);
  // CDF of hg_pdf_cos: (1 - g^2) / (2g) (1 / sqrt(1 + g^2 - 2 g mu) - 1 / (1 + g)).
  return (1.0 - g * g) / (2.0 * g) * (1.0 / std::sqrt(1.0 + g * g - 2.0 * g * mu) - 1.0 / (1.0 + g));
}

}  // namespace skin::mc
