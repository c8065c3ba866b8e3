#pragma once
// Hierarchical point-based subsurface integration (Jensen & Buhler 2002, "A rapid hierarchical
// rendering technique for translucent materials"; the method DJ06 used for its images;
// docs/renderer.md, "Subsurface from a point cloud").
//
//   pass 1: points spread uniformly by area over the translucent meshes, each with the
//           irradiance that enters the skin there, E_p = int L_i (1/pi) F_t(w_i) cos dw
//           (computed by the integrator: integrator.cpp);
//   pass 2: at an exit point x_o, L_ss = F_t(w_o) sum_p K(|x_o - x_p|) E_p A_p, summed over an
//           octree whose nodes stand in for their points where they subtend a small solid angle.
//
// K is the profile R averaged over the disk of area A_p a point stands for (NearFieldKernel):
// R itself where the point is far, the disk's mean where x_o lies in or near it, so that the
// sharp r -> 0 peak of the profile neither vanishes between points nor blows up on them.
// Internal to skin::render (not installed).
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "skin/render/math.hpp"
#include "skin/render/profile_sampler.hpp"

namespace skin::render {

struct SceneData;

// A point on a mesh triangle: barycentrics (b1, b2) of vertices 1 and 2, as Accel's RayHit.
struct SurfaceSample {
  std::uint32_t mesh = 0, prim = 0;
  double b1 = 0, b2 = 0;
};

// Points uniformly by area over the meshes whose material is translucent: n_points in total,
// stratified (each triangle gets its area's share, rounded by a running remainder, placed by a
// Hammersley set in the triangle). Sorted by mesh. *area: the area one point stands for
// [scene units^2] (total / n).
// `seed` rotates the sets (another seed, another set of the same density).
std::vector<SurfaceSample> distribute_points(const SceneData& s, std::size_t n_points, double* area,
                                             std::uint64_t seed = 0);
// The position of a sample [scene units].
Vec3 position_of(const SceneData& s, const SurfaceSample& x);
// Total area of the translucent meshes [scene units^2].
double translucent_area(const SceneData& s);

// The profile of one material averaged over a disk of radius a [mm] centred at distance d from
// the exit point, per channel:
//   K(d) = 1 / (pi a^2) int_disk R(|x|) dx = 1 / (pi a^2) int f(rho) theta(rho; d, a) / pi drho,
// f = 2 pi rho R(rho), theta the half-angle of the circle of radius rho about x_o inside the disk.
// Tabulated for d <= kNear a; beyond it K = R (tabulated too) (the difference is O(a^2 R'' / 8) there: at 3a
// still 10-20 % for skin, at 16a below 0.5 %). K
// integrates to R_d over the plane, as R does.
class NearFieldKernel {
 public:
  static constexpr double kNear = 16.0;
  NearFieldKernel() = default;
  // near_radius [mm] (at most kNear a): the points within it are summed as a kernel-weighted
  // mean (PointCloud::radiant_exitance); 0 = a plain sum.
  NearFieldKernel(const std::array<TabulatedProfile, 3>* profile, double a, double near_radius = 0);
  double operator()(int channel, double d) const;  // [1/mm^2], d [mm]
  // The three channels at once.
  Rgb3 all(double d) const {
    const double near = kNear * a_;
    if (!(a_ > 0)) return exact(d);
    if (d < near) {
      const double t = d / near * kTable;
      const auto i = std::min(static_cast<std::size_t>(t), static_cast<std::size_t>(kTable - 1));
      const double f = t - static_cast<double>(i);
      return near_table_[i] * (1 - f) + near_table_[i + 1] * f;
    }
    if (d >= r_max_ || !(far_scale_ > 0)) return {};
    const double t = (d - near) * far_scale_;
    const auto i = std::min(static_cast<std::size_t>(t), static_cast<std::size_t>(kFar - 1));
    const double f = t - static_cast<double>(i);
    return far_table_[i] * (1 - f) + far_table_[i + 1] * f;
  }
  double r_max() const { return r_max_; }          // beyond it K = 0 in every channel [mm]
  double radius() const { return a_; }
  double near_radius() const { return rho_; }  // [mm]
  // int K dA over the disk of the near radius on a plane, per channel [1].
  double near_integral(int channel) const { return near_integral_[static_cast<std::size_t>(channel)]; }

 private:
  static constexpr int kTable = 512;
  const std::array<TabulatedProfile, 3>* profile_ = nullptr;
  double a_ = 0, r_max_ = 0, rho_ = 0;
  std::array<double, 3> near_integral_{};
  Rgb3 exact(double d) const;  // from the profiles (no table)
  static constexpr int kFar = 4096;
  std::array<Rgb3, kTable + 1> near_table_{};
  std::array<Rgb3, kFar + 1> far_table_{};
  double far_scale_ = 0;  // kFar / (r_max - kNear a)
};

// Points with their area-weighted irradiance E_p A_p, and an octree over them whose nodes carry
// the sum of E A and its centroid (weighted by E A).
class PointCloud {
 public:
  PointCloud() = default;
  // position [scene units], EA = E_p A_p per channel [radiance x mm^2], area [mm^2] of each point.
  // normal: the surface's unit normal at each point (or empty: no normal test in the near mean).
  PointCloud(std::vector<Vec3> position, std::vector<Rgb3> EA, double area, double mm_per_unit,
             std::vector<Vec3> normal = {});

  // sum_p K(|x - x_p|) E_p A_p, using a node's aggregate K(|x - c|) sum E A when x is outside its
  // box and A_node / |x - c|^2 < max_solid_angle (Jensen & Buhler's criterion; 0 = every point).
  // With a near radius rho (NearFieldKernel), the points within rho of x count as a weighted mean:
  //   sum_near K E A / sum_near K A x int_{r < rho} K dA (the plane's integral),
  // which is the plain sum where the points are evenly spread, and takes out how many points
  // happen to fall near x (the density of a stratified cloud varies by tens of per cent over a
  // few spacings, where neighbouring triangles' sets meet; the sum would carry that).
  // With the normal n at x and points' normals, only points facing the same way (n . n_p >
  // kNearCos) join the mean; the rest (the far wall of a cavity, the other side of an ear) are
  // summed plainly, as the probes would find them.
  static constexpr double kNearCos = 0.5;
  Rgb3 radiant_exitance(const Vec3& x, const NearFieldKernel& k, double max_solid_angle, const Vec3* n = nullptr) const;
  // The plain sum over every point (for tests).
  Rgb3 brute_force(const Vec3& x, const NearFieldKernel& k, const Vec3* n = nullptr) const;

  // Exitance cache: radiant exitance at every point (in the order of positions()), then at x the
  // mean of the points within radius h [scene units], weighted 1 - (d / h)^2 (Epanechnikov).
  // False (and nothing set) when no point lies within h. The cache's points are a second set,
  // not the cloud's: at a cloud point the sum always has a point at distance 0, which biases it
  // up where the profile is sharper than the spacing.
  const std::vector<Vec3>& positions() const { return p_; }
  const std::vector<Vec3>& normals() const { return n_; }  // empty when none were given
  void set_exitance(std::vector<Rgb3> M) { M_ = std::move(M); }
  bool has_exitance() const { return !M_.empty(); }
  bool interpolated_exitance(const Vec3& x, double h, Rgb3* M) const;

  std::size_t size() const { return p_.size(); }
  bool empty() const { return p_.empty(); }
  std::size_t nodes() const { return node_.size(); }

 private:
  struct Node {
    Vec3 lo, hi;        // bounds [scene units]
    Vec3 c;             // centroid weighted by E A (geometric mean of the points if dark)
    Rgb3 EA;            // sum of E A
    double area = 0;    // sum of A [mm^2]
    std::uint32_t first = 0, count = 0;  // children (inner) or points (leaf)
    bool leaf = true;
  };
  struct Exitance;
  bool same_side(std::size_t i, const Vec3* n) const;  // point i joins the near mean at x of normal n
  void build(std::uint32_t slot, std::uint32_t begin, std::uint32_t end, int depth);
  static double distance2(const Node& nd, const Vec3& x);
  // f(index, squared distance) for every point within radius h of x.
  template <class F>
  void for_each_within(const Vec3& x, double h, F f) const;
  std::vector<Vec3> p_, n_;
  std::vector<Rgb3> EA_, M_;
  std::vector<Node> node_;
  double area_ = 0, mm_ = 1;
};

}  // namespace skin::render
