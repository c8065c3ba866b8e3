#pragma once
// The BSSRDF of a translucent material seen from one exit point x_o (DJ06 eq 1, subsurface term;
// docs/renderer.md):
//
//   S(x_i, w_i; x_o, w_o) = (1/pi) F_t(w_o) R(|x_o - x_i|) F_t(w_i),   F_t(w) = 1 - rho_dr(theta),
//
// with rho_dr = rho_s x the directional albedo of the surface term (eq 2). Everything that
// evaluates, samples and weights it lives here, as in pbrt-v4's TabulatedBSSRDF, so that the
// probe strategy and the pdf its MIS weight divides by cannot drift apart:
//   - the profile R(r) per channel, its radius sampler and pdf: per linear sRGB channel (RGB
//     rendering, N = 3) or per sampled wavelength (spectral rendering, N = 4: a hero wavelength
//     and three more, each a profile interpolated between the two nearest of a wavelength grid);
//   - the probe segments (axis, channel, radius, angle) through which the integrator finds the
//     entry point x_i, and their one-sample MIS pdf over the three axes and the N channels;
//   - the weight R(|x_o - x_i|) / pdf of a found entry point;
//   - the transmission F_t at the exit (w_o) and at the entry (w_i), and the entry point's
//     BRDF (1/pi) F_t(w_i).
// A Bssrdf is a view built per shading point: it refers to the material's profile tables and
// specular albedo, which must outlive it. Positions are in scene units; profiles in mm.
#include <algorithm>
#include <array>
#include <iosfwd>

#include "skin/render/math.hpp"
#include "skin/render/microfacet.hpp"
#include "skin/render/profile_sampler.hpp"

namespace skin::render {

// The profile of one channel: a table, or the mix w_0 R_0 + w_1 R_1 of two tables (a wavelength
// between two of the spectral grid's, linearly interpolated). The mix is sampled by picking a
// table with probability w_k and drawing from it, so its radius density is the same mix of the
// tables' densities. A single table (w_0 = 1) computes exactly what the table does.
struct ProfileChannel {
  const TabulatedProfile* table[2] = {nullptr, nullptr};
  double weight[2] = {1.0, 0.0};
  ProfileChannel() = default;
  explicit ProfileChannel(const TabulatedProfile& t) : table{&t, nullptr} {}
  ProfileChannel(const TabulatedProfile& a, const TabulatedProfile& b, double w_b)
      : table{&a, &b}, weight{1 - w_b, w_b} {}
  bool mixed() const { return table[1] != nullptr && weight[1] > 0; }
  double eval(double r) const {
    return mixed() ? weight[0] * table[0]->eval(r) + weight[1] * table[1]->eval(r) : table[0]->eval(r);
  }
  double pdf_radius(double r) const {
    return mixed() ? weight[0] * table[0]->pdf_radius(r) + weight[1] * table[1]->pdf_radius(r) : table[0]->pdf_radius(r);
  }
  double pdf_area(double r) const {
    return mixed() ? weight[0] * table[0]->pdf_area(r) + weight[1] * table[1]->pdf_area(r) : table[0]->pdf_area(r);
  }
  // u in [0, 1) picks the table (w_0 : w_1) and, stretched back to [0, 1), the radius in it.
  double sample_radius(double u) const {
    if (!mixed()) return table[0]->sample_radius(u);
    return u < weight[0] ? table[0]->sample_radius(u / weight[0]) : table[1]->sample_radius((u - weight[0]) / weight[1]);
  }
  double r_max() const { return mixed() ? std::max(table[0]->r_max(), table[1]->r_max()) : table[0]->r_max(); }
  double R_d() const { return mixed() ? weight[0] * table[0]->R_d() + weight[1] * table[1]->R_d() : table[0]->R_d(); }
  bool empty() const { return table[0] == nullptr || (table[0]->empty() && !mixed()); }
};

// A probe segment: a chord of the sphere of radius r_max (of the sampled channel) about x_o,
// parallel to one axis of the exit frame, at distance r from x_o. Surface points on it are
// candidate entry points.
struct ProbeSegment {
  Vec3 start;         // scene units
  Vec3 dir;           // unit; the segment is start + t dir, t in [0, length]
  double length = 0;  // scene units
  int axis = 2;       // 0, 1: the tangents s, t of the exit frame; 2: its normal
  int channel = 0;    // profile the radius was drawn from
  double r = 0;       // [mm] distance of the segment's line from x_o
};
std::ostream& operator<<(std::ostream& os, const ProbeSegment& s);

template <int N>
class BasicBssrdf {
 public:
  static constexpr int kChannels = N;
  // Probe axis probabilities. King et al. 2013 and pbrt-v3 use 1/2 for the normal; on smooth skin
  // the tangent probes rarely find a surface (they matter at creases, edges and thin parts), so
  // more of the budget goes to the normal: 3/4, and 1/8 for each tangent. MIS keeps any choice
  // unbiased. Indexed like ProbeSegment::axis.
  static constexpr std::array<double, 3> kAxisProbability{0.125, 0.125, 0.75};

  // profile: R(r) per channel [1/mm^2]; rho_s and albedo: the surface term (albedo may be null
  // when rho_s = 0); x_o and n_o: the exit point [scene units] and its unit shading normal;
  // mm_per_unit: the scene's scale.
  BasicBssrdf(const std::array<ProfileChannel, N>& profile, double rho_s, const SpecularAlbedo* albedo,
              const Vec3& x_o, const Vec3& n_o, double mm_per_unit);

  // --- The profile: R(r) [1/mm^2] at r [mm] (signed; integrates to R_d over the plane), the
  // radius sampler of one channel and its density per unit radius [1/mm].
  double R(int channel, double r) const { return profile_[static_cast<std::size_t>(channel)].eval(r); }
  double sample_r(int channel, double u) const {
    return profile_[static_cast<std::size_t>(channel)].sample_radius(u);
  }
  double pdf_r(int channel, double r) const { return profile_[static_cast<std::size_t>(channel)].pdf_radius(r); }
  double R_d(int channel) const { return profile_[static_cast<std::size_t>(channel)].R_d(); }

  // --- Transmission through the rough surface: rho_dr(theta) = rho_s rho_dr,1(theta) is what the
  // surface term reflects, F_t = 1 - rho_dr what crosses it (at x_o for w_o, at x_i for w_i).
  double rho_dr(double cos_theta) const {
    return rho_s_ > 0 ? rho_s_ * albedo_->rho_dr(cos_theta) : 0.0;
  }
  double F_t(double cos_theta) const { return 1 - rho_dr(cos_theta); }
  // The entry point's BRDF times cos(theta_i): (1/pi) F_t(theta_i) cos(theta_i); 0 below the
  // horizon. Its cosine-sampled continuation weighs f cos / pdf = F_t(theta_i).
  double f_entry_cos(double cos_theta_i) const {
    return cos_theta_i > 0 ? F_t(cos_theta_i) / kPi * cos_theta_i : 0.0;
  }

  // --- Probe sampling (King et al. 2013). Four uniform numbers choose the axis (kAxisProbability),
  // the channel (1/N each), the radius r from that channel's profile and the angle phi about the
  // axis. False when the radius reaches the end of the table (no chord left).
  bool sample_probe(double u_axis, double u_channel, double u_r, double u_phi, ProbeSegment* seg) const;
  // Density per unit area [1/unit^2] with which the probes reach a surface point x_i of unit
  // normal n_i, over all axes and channels (one-sample MIS, balance heuristic; P(channel) = 1/N):
  //   pdf(x_i) = sum_axis sum_channel P(axis) P(channel) |n_i . axis| pdf_area,channel(r_axis),
  // r_axis = distance of x_i from x_o projected onto the plane perpendicular to the axis; a
  // channel's terms count only within its r_max of x_o (its probes are chords of that sphere).
  double pdf_probe(const Vec3& x_i, const Vec3& n_i) const;
  // The weight of an entry point found by a probe, per channel: R(|x_o - x_i|) / pdf(x_i) times
  // the number of candidate points the probe found (one of which was picked uniformly). False
  // where the pdf vanishes. weight: N values.
  bool probe_weight(const Vec3& x_i, const Vec3& n_i, int candidates, double* weight) const;

  // --- The probe set of a camera vertex: N + 1 probes, probe j < N along the normal from channel
  // j's profile, probe N along a tangent (s or t, 1/2 each) from a channel picked 1/N each, taken
  // with probability kTangentProbability (its density counts with that factor). On smooth skin a
  // tangent probe rarely finds the surface: drawing the axis at random for each of N probes left
  // some vertices with fewer normal probes (on a flat slab most of the estimate's spread was that
  // lottery); the set always has N normal probes, and sometimes a tangent probe for creases,
  // edges and thin parts (the probability 1/4 was chosen on the head scene's error per CPU time:
  // docs/benchmarks.md). The entry points of all of them are combined by a multi-sample
  // MIS (Veach 1997, sec. 9.2): for channel c, a point found by probe j weighs
  //   alpha_cj R_c(|x_o - x_i|) / sum_k alpha_ck pdf_k(x_i),   alpha_cj = kOwnChannelWeight if j = c, else 1,
  // summed over every point every probe found. The weights alpha_cj pdf_j / sum_k alpha_ck pdf_k
  // sum to one over the probes, so the estimate is unbiased for any alpha; alpha = 1 is the
  // balance heuristic, alpha -> infinity estimates each channel from its own probe (exact on a
  // flat, uniformly lit slab, worse on a face: one entry point per channel, and the light varies
  // across the red footprint). alpha = 2: measured on the head and the default scene's back-lit
  // fin (docs/renderer.md, "Why a set, and why alpha = 2").
  static constexpr int kSetProbes = N + 1;
  static constexpr double kOwnChannelWeight = 2.0;
  static constexpr double kTangentProbability = 0.25;
  // Probe j of the set: u_a (used by the tangent probe only) decides whether it is taken and
  // picks its axis and channel; u_r and u_phi as in sample_probe. False: no probe.
  bool sample_set_probe(int j, double u_a, double u_r, double u_phi, ProbeSegment* seg) const;
  // Density per unit area [1/unit^2] with which probe j of the set reaches x_i (normal n_i).
  double pdf_set_probe(int j, const Vec3& x_i, const Vec3& n_i) const;
  // The weight above per channel of a point x_i found by probe j; false where it vanishes in
  // every channel.
  bool probe_set_weight(int j, const Vec3& x_i, const Vec3& n_i, double* weight) const;

  const Frame& frame() const { return frame_; }
  const Vec3& x_o() const { return x_o_; }
  const ProfileChannel& channel(int c) const { return profile_[static_cast<std::size_t>(c)]; }

 private:
  // A chord of the sphere of channel `channel`'s r_max parallel to axis `axis` (0, 1: the
  // tangents s, t; 2: the normal) at the radius u_r draws from that channel's profile.
  bool probe(int axis, int channel, double u_r, double u_phi, ProbeSegment* seg) const;
  // Density per unit area [1/unit^2] of the probes of each axis and channel at x_i:
  // |n_i . axis| pdf_area,channel(r_axis), 0 beyond the channel's r_max. out[axis][channel].
  void axis_channel_pdfs(const Vec3& x_i, const Vec3& n_i, std::array<std::array<double, N>, 3>* out) const;
  std::array<ProfileChannel, N> profile_;
  double rho_s_;
  const SpecularAlbedo* albedo_;
  Vec3 x_o_;
  Frame frame_;
  double mm_;  // mm per scene unit
};
template <int N>
std::ostream& operator<<(std::ostream& os, const BasicBssrdf<N>& b);

// RGB rendering (the paper's method): one profile per linear sRGB channel, the material's tables.
class Bssrdf : public BasicBssrdf<3> {
 public:
  Bssrdf(const std::array<TabulatedProfile, 3>& profile, double rho_s, const SpecularAlbedo* albedo, const Vec3& x_o,
         const Vec3& n_o, double mm_per_unit)
      : BasicBssrdf<3>({ProfileChannel(profile[0]), ProfileChannel(profile[1]), ProfileChannel(profile[2])}, rho_s,
                       albedo, x_o, n_o, mm_per_unit) {}
  using BasicBssrdf<3>::probe_weight;
  bool probe_weight(const Vec3& x_i, const Vec3& n_i, int candidates, Rgb3* weight) const {
    double w[3];
    if (!probe_weight(x_i, n_i, candidates, w)) return false;
    *weight = {w[0], w[1], w[2]};
    return true;
  }
};
// Spectral rendering: one profile per sampled wavelength (hero wavelength + 3, Wilkie et al. 2014).
using SpectralBssrdf = BasicBssrdf<4>;

}  // namespace skin::render
