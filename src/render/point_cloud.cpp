// Point-based subsurface integration (Jensen & Buhler 2002): the points, the near-field kernel and
// the octree. The irradiance of the points comes from the integrator (integrator.cpp).
#include "point_cloud.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "scene_data.hpp"
#include "skin/render/sampling.hpp"
#include "skin/util/random.hpp"

namespace skin::render {

using skin::util::Pcg32;

namespace {

double triangle_area(const Mesh& m, const std::array<std::uint32_t, 3>& t) {
  return 0.5 * length(cross(m.position[t[1]] - m.position[t[0]], m.position[t[2]] - m.position[t[0]]));
}

double radical_inverse_2(std::uint32_t k) {
  k = (k << 16u) | (k >> 16u);
  k = ((k & 0x00ff00ffu) << 8u) | ((k & 0xff00ff00u) >> 8u);
  k = ((k & 0x0f0f0f0fu) << 4u) | ((k & 0xf0f0f0f0u) >> 4u);
  k = ((k & 0x33333333u) << 2u) | ((k & 0xccccccccu) >> 2u);
  k = ((k & 0x55555555u) << 1u) | ((k & 0xaaaaaaaau) >> 1u);
  return static_cast<double>(k) * 0x1p-32;
}

}  // namespace

double translucent_area(const SceneData& s) {
  double total = 0;
  for (const Mesh& m : s.meshes)
    if (s.materials[m.material].translucent())
      for (const auto& t : m.triangles) total += triangle_area(m, t);
  return total;
}

Vec3 position_of(const SceneData& s, const SurfaceSample& x) {
  const Mesh& m = s.meshes[x.mesh];
  const auto& t = m.triangles[x.prim];
  return m.position[t[0]] * (1 - x.b1 - x.b2) + m.position[t[1]] * x.b1 + m.position[t[2]] * x.b2;
}

std::vector<SurfaceSample> distribute_points(const SceneData& s, std::size_t n_points, double* area,
                                             std::uint64_t seed) {
  std::vector<SurfaceSample> out;
  const double total = translucent_area(s);
  *area = n_points > 0 ? total / static_cast<double>(n_points) : 0.0;
  if (n_points == 0 || !(total > 0)) return out;
  out.reserve(n_points + 1);
  // A triangle gets round(carry + its share) points; the remainder carries to the next one, so
  // the count is exact and every stretch of triangles gets its area's share to within one point.
  double carry = 0;
  for (std::size_t mi = 0; mi < s.meshes.size(); ++mi) {
    const Mesh& m = s.meshes[mi];
    if (!s.materials[m.material].translucent()) continue;
    for (std::size_t ti = 0; ti < m.triangles.size(); ++ti) {
      const double share = carry + triangle_area(m, m.triangles[ti]) / *area;
      const auto n = static_cast<std::uint32_t>(std::max(0.0, std::floor(share + 0.5)));
      carry = share - n;
      // A Hammersley set in the unit square, rotated by a per-triangle offset (Cranley-Patterson)
      // and mapped to the triangle by the square-root warp.
      Pcg32 rng(0x5eedull + mi + (seed << 32u), ti);
      const double ou = rng.uniform(), ov = rng.uniform();
      for (std::uint32_t k = 0; k < n; ++k) {
        double u = (k + 0.5) / n + ou, v = radical_inverse_2(k) + ov;
        u -= std::floor(u);
        v -= std::floor(v);
        const double su = std::sqrt(u);
        out.push_back({static_cast<std::uint32_t>(mi), static_cast<std::uint32_t>(ti), su * (1 - v), su * v});
      }
    }
  }
  return out;
}

NearFieldKernel::NearFieldKernel(const std::array<TabulatedProfile, 3>* profile, double a, double near_radius)
    : profile_(profile), a_(a), rho_(near_radius) {
  r_max_ = kNear * a;
  for (const TabulatedProfile& p : *profile) r_max_ = std::max(r_max_, p.r_max());
  if (!(a > 0)) return;
  // Gauss-Legendre, 4 nodes, on pieces no longer than a / 16 between the table's radii and the
  // kinks of theta (|d - a| and d + a): f is linear within a piece of the table.
  static constexpr std::array<double, 4> x{-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
  static constexpr std::array<double, 4> w{0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
  for (int c = 0; c < 3; ++c) {
    const TabulatedProfile& p = (*profile)[static_cast<std::size_t>(c)];
    for (int j = 0; j <= kTable; ++j) {
      const double d = kNear * a * j / kTable;
      const double lo = std::max(0.0, d - a), hi = d + a;
      std::vector<double> cuts{lo, hi, std::abs(d - a)};
      for (const double r : p.radii())
        if (r > lo && r < hi) cuts.push_back(r);
      std::sort(cuts.begin(), cuts.end());
      double sum = 0;
      for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
        const double a0 = std::max(lo, cuts[i]), a1 = std::min(hi, cuts[i + 1]);
        if (!(a1 > a0)) continue;
        const int pieces = std::max(1, static_cast<int>(std::ceil((a1 - a0) / (a / 16))));
        const double h = (a1 - a0) / pieces;
        for (int q = 0; q < pieces; ++q)
          for (std::size_t g = 0; g < 4; ++g) {
            const double rho = a0 + h * (q + 0.5 * (x[g] + 1));
            double theta = 0;
            if (rho <= a - d) theta = kPi;
            else if (rho > d - a && rho < d + a && d > 0)
              theta = std::acos(std::clamp((rho * rho + d * d - a * a) / (2 * rho * d), -1.0, 1.0));
            sum += 0.5 * h * w[g] * 2 * kPi * rho * p.eval(rho) * theta / kPi;
          }
      }
      near_table_[static_cast<std::size_t>(j)][c] = sum / (kPi * a * a);
    }
  }
  // Beyond kNear a: R itself, tabulated in 4096 even steps to r_max (all three channels read at
  // one index; a step is r_max / 4096, ~0.01 mm, against R's millimetres of scale there).
  const double near = kNear * a;
  if (r_max_ > near) {
    far_scale_ = kFar / (r_max_ - near);
    for (int j = 0; j <= kFar; ++j) {
      const double d = near + j / far_scale_;
      for (int c = 0; c < 3; ++c) far_table_[static_cast<std::size_t>(j)][c] = (*profile)[static_cast<std::size_t>(c)].eval(d);
    }
  }
  // int_0^rho K(r) 2 pi r dr by the midpoint rule on the kernel itself (linear between its
  // table's nodes, rho <= kNear a).
  rho_ = std::min(rho_, kNear * a);
  constexpr int kSteps = 4 * kTable;
  for (int c = 0; c < 3; ++c) {
    double t = 0;
    for (int i = 0; i < kSteps; ++i) {
      const double r = rho_ * (i + 0.5) / kSteps;
      t += (*this)(c, r) * 2 * kPi * r;
    }
    near_integral_[static_cast<std::size_t>(c)] = t * rho_ / kSteps;
  }
}

Rgb3 NearFieldKernel::exact(double d) const {
  Rgb3 out;
  for (int c = 0; c < 3; ++c) out[c] = (*profile_)[static_cast<std::size_t>(c)].eval(d);
  return out;
}

double NearFieldKernel::operator()(int channel, double d) const { return all(d)[channel]; }

PointCloud::PointCloud(std::vector<Vec3> position, std::vector<Rgb3> EA, double area, double mm_per_unit,
                       std::vector<Vec3> normal)
    : p_(std::move(position)), n_(std::move(normal)), EA_(std::move(EA)), area_(area), mm_(mm_per_unit) {
  if (!n_.empty() && n_.size() != p_.size())
    throw std::invalid_argument("PointCloud: " + std::to_string(n_.size()) + " normals for " + std::to_string(p_.size()) + " points");
  if (p_.empty()) return;
  node_.reserve(p_.size() / 3 + 8);
  node_.emplace_back();
  build(0, 0, static_cast<std::uint32_t>(p_.size()), 0);
}

// Fills node_[slot] for the points [begin, end): bounds and aggregates, and (over kLeaf points)
// its children, appended contiguously, one per non-empty octant of the box (points reordered
// stably by octant: deterministic).
void PointCloud::build(std::uint32_t slot, std::uint32_t begin, std::uint32_t end, int depth) {
  constexpr std::uint32_t kLeaf = 8;
  constexpr int kMaxDepth = 30;  // 7 x 30 + 1 < the traversal stack's 256
  Node nd;
  nd.lo = nd.hi = p_[begin];
  Vec3 cw, cg;
  double wsum = 0;
  for (std::uint32_t i = begin; i < end; ++i) {
    const Vec3& p = p_[i];
    nd.lo = {std::min(nd.lo.x, p.x), std::min(nd.lo.y, p.y), std::min(nd.lo.z, p.z)};
    nd.hi = {std::max(nd.hi.x, p.x), std::max(nd.hi.y, p.y), std::max(nd.hi.z, p.z)};
    nd.EA += EA_[i];
    const double w = std::max(0.0, EA_[i].r + EA_[i].g + EA_[i].b);
    cw += p * w;
    wsum += w;
    cg += p;
  }
  const std::uint32_t count = end - begin;
  nd.area = count * area_;
  nd.c = wsum > 0 ? cw / wsum : cg / static_cast<double>(count);
  nd.first = begin;
  nd.count = count;
  if (count <= kLeaf || depth >= kMaxDepth) {
    node_[slot] = nd;
    return;
  }
  const Vec3 mid = (nd.lo + nd.hi) * 0.5;
  const auto octant = [&](const Vec3& p) {
    return (p.x > mid.x ? 1u : 0u) | (p.y > mid.y ? 2u : 0u) | (p.z > mid.z ? 4u : 0u);
  };
  std::array<std::uint32_t, 9> start{};
  for (std::uint32_t i = begin; i < end; ++i) ++start[octant(p_[i]) + 1];
  for (std::size_t o = 1; o < start.size(); ++o) start[o] += start[o - 1];
  const std::vector<Vec3> p(p_.begin() + begin, p_.begin() + end);
  const std::vector<Rgb3> ea(EA_.begin() + begin, EA_.begin() + end);
  const std::vector<Vec3> nn = n_.empty() ? std::vector<Vec3>() : std::vector<Vec3>(n_.begin() + begin, n_.begin() + end);
  std::array<std::uint32_t, 8> fill{};
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::uint32_t o = octant(p[i]);
    const std::uint32_t at = begin + start[o] + fill[o]++;
    p_[at] = p[i];
    EA_[at] = ea[i];
    if (!nn.empty()) n_[at] = nn[i];
  }
  std::uint32_t children = 0;
  for (std::size_t o = 0; o < 8; ++o) children += start[o + 1] > start[o] ? 1 : 0;
  if (children == 1) {  // all in one octant of a degenerate box (coincident points): a leaf
    node_[slot] = nd;
    return;
  }
  nd.leaf = false;
  nd.first = static_cast<std::uint32_t>(node_.size());
  nd.count = children;
  node_[slot] = nd;
  node_.resize(node_.size() + children);
  std::uint32_t c = nd.first;
  for (std::size_t o = 0; o < 8; ++o)
    if (start[o + 1] > start[o]) build(c++, begin + start[o], begin + start[o + 1], depth + 1);
}

// The exitance at x: points nearer than the kernel's near radius (and facing the way x faces) go
// into a sum of their own, normalised by the sum of their weights K A against the kernel's planar
// integral over that disk; the rest into the plain sum.
struct PointCloud::Exitance {
  const NearFieldKernel& k;
  Rgb3 far, near, weight;
  void add(double d, const Rgb3& ea, double area, bool same_side) {
    const Rgb3 kk = k.all(d);
    const Rgb3 v{kk.r * ea.r, kk.g * ea.g, kk.b * ea.b};
    if (d < k.near_radius() && same_side) {
      near += v;
      weight += kk * area;
    } else {
      far += v;
    }
  }
  Rgb3 total() const {
    if (!(k.near_radius() > 0)) return far + near;
    const auto one = [&](double v, double w, int c) { return w > 0 ? v * k.near_integral(c) / w : 0.0; };
    return far + Rgb3{one(near.r, weight.r, 0), one(near.g, weight.g, 1), one(near.b, weight.b, 2)};
  }
};

bool PointCloud::same_side(std::size_t i, const Vec3* n) const {
  return n == nullptr || n_.empty() || dot(*n, n_[i]) > kNearCos;
}

Rgb3 PointCloud::radiant_exitance(const Vec3& x, const NearFieldKernel& k, double max_solid_angle, const Vec3* n) const {
  Exitance out{k, {}, {}, {}};
  if (node_.empty()) return {};
  const double r_max = k.r_max() / mm_;  // [scene units]
  std::uint32_t stack[256];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& nd = node_[stack[--top]];
    const double d_box2 = distance2(nd, x);
    if (d_box2 > r_max * r_max) continue;
    if (nd.leaf) {
      for (std::uint32_t i = nd.first; i < nd.first + nd.count; ++i)
        out.add(length(x - p_[i]) * mm_, EA_[i], area_, same_side(i, n));
      continue;
    }
    if (d_box2 > 0) {
      const double d = length(x - nd.c) * mm_;
      if (nd.area < max_solid_angle * d * d) {
        out.add(d, nd.EA, nd.area, true);
        continue;
      }
    }
    for (std::uint32_t c = nd.first; c < nd.first + nd.count; ++c) stack[top++] = c;
  }
  return out.total();
}

// Squared distance from x to a node's box (0 inside).
double PointCloud::distance2(const Node& nd, const Vec3& x) {
  const double dx = std::max({nd.lo.x - x.x, 0.0, x.x - nd.hi.x});
  const double dy = std::max({nd.lo.y - x.y, 0.0, x.y - nd.hi.y});
  const double dz = std::max({nd.lo.z - x.z, 0.0, x.z - nd.hi.z});
  return dx * dx + dy * dy + dz * dz;
}

template <class F>
void PointCloud::for_each_within(const Vec3& x, double h, F f) const {
  if (node_.empty()) return;
  const double h2 = h * h;
  std::uint32_t stack[256];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& nd = node_[stack[--top]];
    if (distance2(nd, x) >= h2) continue;
    if (!nd.leaf) {
      for (std::uint32_t c = nd.first; c < nd.first + nd.count; ++c) stack[top++] = c;
      continue;
    }
    for (std::uint32_t i = nd.first; i < nd.first + nd.count; ++i) {
      const Vec3 v = x - p_[i];
      const double d2 = dot(v, v);
      if (d2 < h2) f(i, d2);
    }
  }
}

bool PointCloud::interpolated_exitance(const Vec3& x, double h, Rgb3* M) const {
  if (node_.empty() || M_.empty()) return false;
  Rgb3 sum;
  double wsum = 0;
  const double h2 = h * h;
  for_each_within(x, h, [&](std::uint32_t i, double d2) {
    const double w = 1 - d2 / h2;
    sum += M_[i] * w;
    wsum += w;
  });
  if (!(wsum > 0)) return false;
  *M = sum / wsum;
  return true;
}

Rgb3 PointCloud::brute_force(const Vec3& x, const NearFieldKernel& k, const Vec3* n) const {
  Exitance out{k, {}, {}, {}};
  for (std::size_t i = 0; i < p_.size(); ++i) out.add(length(x - p_[i]) * mm_, EA_[i], area_, same_side(i, n));
  return out.total();
}

}  // namespace skin::render
