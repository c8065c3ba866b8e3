// The BSSRDF at an exit point (include/skin/render/bssrdf.hpp; docs/renderer.md, "Sampling the
// entry point"): probe segments and the MIS pdf they are weighted with, side by side.
#include "skin/render/bssrdf.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <ostream>

namespace skin::render {

template <int N>
BasicBssrdf<N>::BasicBssrdf(const std::array<ProfileChannel, N>& profile, double rho_s, const SpecularAlbedo* albedo,
                            const Vec3& x_o, const Vec3& n_o, double mm_per_unit)
    : profile_(profile), rho_s_(rho_s), albedo_(albedo), x_o_(x_o), frame_(Frame::from_normal(n_o)), mm_(mm_per_unit) {
  assert(rho_s == 0 || albedo != nullptr);  // built per shading point: a debug check only
}

template <int N>
bool BasicBssrdf<N>::probe(int axis_index, int channel, double u_r, double u_phi, ProbeSegment* seg) const {
  // The axis, and the two directions spanning the plane perpendicular to it.
  Vec3 axis, ta, tb;
  if (axis_index == 2) {
    axis = frame_.n; ta = frame_.s; tb = frame_.t;
  } else if (axis_index == 0) {
    axis = frame_.s; ta = frame_.t; tb = frame_.n;
  } else {
    axis = frame_.t; ta = frame_.n; tb = frame_.s;
  }
  seg->axis = axis_index;
  seg->channel = channel;
  const ProfileChannel& prof = profile_[static_cast<std::size_t>(channel)];
  if (prof.empty()) return false;
  const double r_max_mm = prof.r_max();
  seg->r = prof.sample_radius(u_r);
  if (!(seg->r < r_max_mm)) return false;
  const double phi = 2 * kPi * u_phi;
  const double r = seg->r / mm_, r_max = r_max_mm / mm_;
  const double half = std::sqrt(r_max * r_max - r * r);
  const Vec3 base = x_o_ + (ta * std::cos(phi) + tb * std::sin(phi)) * r;
  seg->start = base + axis * half;
  seg->dir = -axis;
  seg->length = 2 * half;
  return true;
}

namespace {
int channel_of(double u, int n) { return static_cast<int>(std::min(static_cast<std::size_t>(u * n), static_cast<std::size_t>(n - 1))); }
}  // namespace

template <int N>
bool BasicBssrdf<N>::sample_probe(double u_axis, double u_channel, double u_r, double u_phi, ProbeSegment* seg) const {
  const int axis = u_axis < kAxisProbability[2] ? 2 : u_axis < kAxisProbability[2] + kAxisProbability[0] ? 0 : 1;
  return probe(axis, channel_of(u_channel, N), u_r, u_phi, seg);
}

template <int N>
bool BasicBssrdf<N>::sample_set_probe(int j, double u_a, double u_r, double u_phi, ProbeSegment* seg) const {
  if (j < N) return probe(2, j, u_r, u_phi, seg);
  // The tangent probe, taken with probability kTangentProbability (u_a below it); u_a stretched
  // to [0, 1): its lower half picks s, the upper t; stretched again, the channel.
  if (u_a >= kTangentProbability) return false;
  u_a /= kTangentProbability;
  const int axis = u_a < 0.5 ? 0 : 1;
  return probe(axis, channel_of(u_a < 0.5 ? 2 * u_a : 2 * u_a - 1, N), u_r, u_phi, seg);
}

template <int N>
void BasicBssrdf<N>::axis_channel_pdfs(const Vec3& x_i, const Vec3& n_i, std::array<std::array<double, N>, 3>* out) const {
  const Vec3 dl = frame_.to_local(x_i - x_o_);
  const Vec3 nl = frame_.to_local(n_i);
  const double r_proj[3] = {std::sqrt(dl.y * dl.y + dl.z * dl.z), std::sqrt(dl.x * dl.x + dl.z * dl.z),
                            std::sqrt(dl.x * dl.x + dl.y * dl.y)};  // about the s, t, n axes
  const double n_abs[3] = {std::abs(nl.x), std::abs(nl.y), std::abs(nl.z)};
  // A channel's probes are chords of its sphere of radius r_max: they reach no point beyond it.
  const double dist_mm = length(x_i - x_o_) * mm_;
  for (std::size_t ax = 0; ax < 3; ++ax)
    for (std::size_t ch = 0; ch < N; ++ch)
      (*out)[ax][ch] = dist_mm <= profile_[ch].r_max()
                           ? n_abs[ax] * profile_[ch].pdf_area(r_proj[ax] * mm_) * mm_ * mm_
                           : 0.0;
}

template <int N>
double BasicBssrdf<N>::pdf_probe(const Vec3& x_i, const Vec3& n_i) const {
  std::array<std::array<double, N>, 3> p;
  axis_channel_pdfs(x_i, n_i, &p);
  double pdf = 0;  // per unit area [1/unit^2]
  for (std::size_t ax = 0; ax < 3; ++ax)
    for (std::size_t ch = 0; ch < N; ++ch) pdf += kAxisProbability[ax] * (1.0 / N) * p[ax][ch];
  return pdf;
}

template <int N>
bool BasicBssrdf<N>::probe_weight(const Vec3& x_i, const Vec3& n_i, int candidates, double* weight) const {
  const double pdf = pdf_probe(x_i, n_i);
  if (!(pdf > 0)) return false;
  const double dist_mm = length(x_i - x_o_) * mm_;
  for (int ch = 0; ch < N; ++ch) weight[ch] = R(ch, dist_mm) * mm_ * mm_ * candidates / pdf;
  return true;
}

template <int N>
double BasicBssrdf<N>::pdf_set_probe(int j, const Vec3& x_i, const Vec3& n_i) const {
  std::array<std::array<double, N>, 3> p;
  axis_channel_pdfs(x_i, n_i, &p);
  if (j < N) return p[2][static_cast<std::size_t>(j)];
  double pdf = 0;
  for (std::size_t ch = 0; ch < N; ++ch) pdf += kTangentProbability * (0.5 / N) * (p[0][ch] + p[1][ch]);
  return pdf;
}

template <int N>
bool BasicBssrdf<N>::probe_set_weight(int j, const Vec3& x_i, const Vec3& n_i, double* weight) const {
  std::array<std::array<double, N>, 3> p;
  axis_channel_pdfs(x_i, n_i, &p);
  double pdf = 0;  // the set's densities summed with weight 1
  for (std::size_t ch = 0; ch < N; ++ch) pdf += p[2][ch] + kTangentProbability * (0.5 / N) * (p[0][ch] + p[1][ch]);
  const double dist_mm = length(x_i - x_o_) * mm_;
  bool any = false;
  for (int c = 0; c < N; ++c) {
    const double den = pdf + (kOwnChannelWeight - 1) * p[2][static_cast<std::size_t>(c)];
    const double alpha = j == c ? kOwnChannelWeight : 1.0;
    weight[c] = den > 0 ? alpha * R(c, dist_mm) * mm_ * mm_ / den : 0.0;
    any = any || weight[c] != 0;
  }
  return any;
}

template <int N>
std::ostream& operator<<(std::ostream& os, const BasicBssrdf<N>& b) {
  os << "Bssrdf{x_o=" << b.x_o() << ", n_o=" << b.frame().n << ", rho_dr(1)=" << b.rho_dr(1.0) << ", R_d=(";
  for (int c = 0; c < N; ++c) os << (c ? ", " : "") << b.R_d(c);
  return os << ")}";
}

template class BasicBssrdf<3>;
template class BasicBssrdf<4>;
template std::ostream& operator<<(std::ostream&, const BasicBssrdf<3>&);
template std::ostream& operator<<(std::ostream&, const BasicBssrdf<4>&);

std::ostream& operator<<(std::ostream& os, const ProbeSegment& s) {
  return os << "ProbeSegment{axis=" << s.axis << ", channel=" << s.channel << ", r=" << s.r << " mm, start=" << s.start
            << ", dir=" << s.dir << ", length=" << s.length << '}';
}

}  // namespace skin::render
