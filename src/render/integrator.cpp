// The path tracer (docs/renderer.md). Per camera sample: trace a path; at a diffuse surface, a
// Lambertian vertex; at a translucent one (skin, layered) two terms of DJ06 eq 1:
//   surface:    the Torrance-Sparrow lobe f_s scaled by rho_s (direct light with MIS, and a
//               sampled continuation);
//   subsurface: S(x_i, w_i; x_o, w_o) = (1/pi) F_t(w_o) R(|x_o - x_i|) F_t(w_i), with
//               F_t(w) = 1 - rho_dr(theta) (eq 2 scaled by rho_s): light not reflected by the
//               surface term enters, and light leaving is reduced by what the surface term
//               would have reflected back in. The factor is applied twice: once at the camera-
//               side point x_o (for w_o) and once inside the BRDF of the entry point x_i (for
//               w_i), so that a uniformly lit flat slab has radiance
//               rho_dr(theta_o) + (1 - rho_dr(theta_o)) R_d (1 - rho_dr_mean).
// The entry point x_i is importance-sampled by radius from the tabulated profiles with probe
// rays along the normal and the two tangents, combined with MIS over axes and channels; the
// profiles, the probes, their pdf and F_t are one object, Bssrdf (skin/render/bssrdf.hpp). Every
// light pairs its sampler with its pdf (lights.hpp).
// The path carries RGB (the paper's method) or the values at four sampled wavelengths (spectral
// rendering): the Shading policies below are all that differs.
#include <tbb/blocked_range.h>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <type_traits>
#include <unordered_map>
#include <variant>

#include "film.hpp"
#include "point_cloud.hpp"
#include "scene_impl.hpp"
#include "skin/render/bssrdf.hpp"
#include "spectral.hpp"
#include "skin/util/cancel.hpp"
#include "skin/util/error.hpp"

namespace skin::render {

using skin::util::InputError;
using skin::util::format_number;
using skin::util::require_non_negative;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Surface {
  Vec3 p, ng, ns;
  Vec2 uv;
  bool has_uv = false;
  const Material* mat = nullptr;
  std::size_t mesh = 0;
};

// Where a path is and how it got there: the ray to trace next, and the direction's pdf for MIS.
struct PathState {
  Vec3 o, d;
  double prev_pdf = 0;     // solid-angle pdf of the direction that produced this ray
  bool prev_delta = true;  // true: no MIS against lights for what the ray hits (camera ray)
  Vec3 prev_n;             // shading normal at the vertex the ray left (environment pdf)
};

// What a path carries and how the scene's RGB data turns into it. RGB rendering: linear sRGB,
// the material's three channel profiles, the data as they are.
struct RgbShading {
  using Value = Rgb3;
  using Bssrdf = render::Bssrdf;
  static constexpr int kChannels = 3;
  static Value one() { return {1, 1, 1}; }
  Bssrdf bssrdf(const TranslucentMaterial& m, const Vec3& x, const Vec3& n, double mm) const {
    return Bssrdf(m.profile, m.rho_s, m.specular_albedo.get(), x, n, mm);
  }
  // A light's RGB radiance (light: its index, lights.size() for the environment).
  const Value& emitted(const Rgb3& L, std::size_t) const { return L; }
  const Value& reflectance(const Rgb3& albedo) const { return albedo; }
  // The albedo texture's modulation of the subsurface term: texture / R_d(reference).
  Value texture(const TranslucentMaterial& m, const Rgb3& texel) const { return texel * m.texture_normalisation; }
  static Value from(const double* w) { return {w[0], w[1], w[2]}; }
};

// Spectral rendering: the values at the camera sample's four wavelengths; lights, albedos and
// textures upsampled (spectral.hpp), skin profiles per wavelength.
struct SpectralShading {
  using Value = SampledSpectrum;
  using Bssrdf = SpectralBssrdf;
  static constexpr int kChannels = kWavelengths;
  const std::vector<SpectralEmission>* emission;  // per light, then the environment
  SampledWavelengths wl;
  static Value one() { return Value::constant(1); }
  Bssrdf bssrdf(const TranslucentMaterial& m, const Vec3& x, const Vec3& n, double mm) const {
    return Bssrdf(m.spectral->channels(wl), m.rho_s, m.specular_albedo.get(), x, n, mm);
  }
  Value emitted(const Rgb3& L, std::size_t light) const { return (*emission)[light](L, wl); }
  Value reflectance(const Rgb3& albedo) const { return RgbUpsampling::get()(albedo, wl); }
  Value texture(const TranslucentMaterial& m, const Rgb3& texel) const {
    Value t = RgbUpsampling::get()(texel, wl);
    for (int j = 0; j < kWavelengths; ++j) {
      const double ref = (*m.spectral_texture_reference)(wl.lambda[static_cast<std::size_t>(j)]);
      t[j] = ref > 1e-6 ? t[j] / ref : 0.0;
    }
    return t;
  }
  static Value from(const double* w) { return {{w[0], w[1], w[2], w[3]}}; }
};

// The subsurface term from point clouds (point_cloud.hpp): a cloud per translucent material (by
// index; empty for the others) and the near-field kernel of each translucent material and
// parameter-map node, by address.
struct PointSubsurface {
  std::vector<PointCloud> cloud;
  std::unordered_map<const TranslucentMaterial*, NearFieldKernel> kernel;
  double max_solid_angle = 0;
  double h = 0;  // [scene units] radius of the exitance cache's interpolation; 0: sum at x_o
  double spacing = 0;  // [mm]
  std::vector<PointCloud> cache;  // per material: the exitance cache (PointCloud::set_exitance)
};

// Where a path starts: the camera (depth 0, no MIS for what it hits) or a vertex already on the
// surface (the irradiance of a cloud's point continues its paths from depth 1).
struct PathStart {
  int depth = 0;
  double prev_pdf = 0;     // solid-angle pdf of the first ray's direction
  bool prev_delta = true;  // true: no MIS against lights for what the first ray hits
  Vec3 prev_n;             // shading normal at the origin
};

class Integrator {
 public:
  Integrator(const SceneData& s, const Accel& a, int max_depth, const PointSubsurface* points = nullptr)
      : s_(s), a_(a), max_depth_(max_depth), eps_(1e-5 * a.extent()), points_(points) {}

  // *translucent (if given): whether the first surface the ray meets is translucent.
  template <class Shading>
  typename Shading::Value Li(Vec3 o, Vec3 d, Sampler& rng, const Shading& sh, bool* translucent = nullptr,
                             const PathStart& start = {}) const;
  // The irradiance that enters a translucent surface at a point, per channel (RGB):
  // E = int L_i (1/pi) F_t(w_i) cos dw (the entry point's BRDF of the probe path), from `samples`
  // rounds of next-event estimation to every light and one cosine-sampled path each. The stream
  // of round j is (seed, index, j): the result does not depend on the thread.
  Rgb3 entry_irradiance(const SurfaceSample& at, std::uint64_t seed, std::uint64_t index, int samples, Vec3* position,
                        Vec3* normal) const;
  // The shading normal at a point of a mesh (outward, the mesh's own orientation).
  Vec3 normal_at(const SurfaceSample& at) const;

 private:
  // face_ray: turn the normals toward -d (two-sided shading of what a ray sees); otherwise keep
  // the mesh's own orientation (its normals, else its winding), outward for closed meshes.
  Surface surface(const RayHit& h, const Vec3& d, bool face_ray = true) const;
  // Direct light at a point: one sample of every light (next-event estimation over all of
  // them, rather than one picked at random: scenes have few lights, and the shadow rays are
  // cheap next to the variance a random pick adds), each weighted by MIS against the BSDF.
  // f(wi) returns the BSDF value times cos(theta_i), pdf(wi) its sampling density.
  template <class Shading, class F, class P>
  typename Shading::Value direct(const Shading& sh, const Vec3& p, const Vec3& ns, const Vec3& ng, Sampler& rng, F f,
                                 P pdf) const;
  // Area light hit along a ray before t_max: radiance, the light's index and its solid-angle pdf
  // for MIS (n: normal at the ray's origin, as the light's pdf takes it).
  bool hit_area_light(const Vec3& o, const Vec3& n, const Vec3& d, double t_max, Rgb3* Le, std::size_t* index,
                      double* pdf) const;
  bool visible(const Vec3& p, const Vec3& n, const Vec3& wi, double dist) const;
  Vec3 offset(const Vec3& p, const Vec3& n, const Vec3& w) const { return p + n * (dot(w, n) > 0 ? eps_ : -eps_); }
  // A vertex of a path: the material's own terms added to L (beta: the path's throughput), and
  // the path continued from it (false: it ends). One per material type (Material::type).
  template <class Shading>
  bool vertex(const DiffuseMaterial& m, const Surface& x, int depth, Sampler& rng, const Shading& sh,
              typename Shading::Value& L, typename Shading::Value& beta, PathState& path) const;
  template <class Shading>
  bool vertex(const TranslucentMaterial& m, const Surface& x, int depth, Sampler& rng, const Shading& sh,
              typename Shading::Value& L, typename Shading::Value& beta, PathState& path) const;
  // Entry points and their weights R / pdf per channel (sample_entries).
  template <class Value>
  struct Entry {
    Surface x;
    Value weight;
    int slot;  // probe x kMaxHits + candidate: its block of sampler dimensions
  };
  static constexpr int kMaxHits = 8;  // candidates per probe
  // Sampler blocks: per depth up to kBlockDepths, one for the vertex, one per entry point (probe,
  // candidate) for its light, one for the continuation.
  static constexpr int kBlockDepths = 3;
  static constexpr int kBlocksPerDepth = 2 + 5 * kMaxHits;  // up to N + 1 = 5 probes
  // probe_set: the BSSRDF's probe set (camera vertices); otherwise one probe of a random axis and
  // channel (deeper vertices, where more probes cost more than they gain).
  template <class Shading>
  int sample_entries(const Surface& xo, const typename Shading::Bssrdf& bssrdf, Sampler& rng, bool probe_set,
                     Entry<typename Shading::Value>* out) const;

  const SceneData& s_;
  const Accel& a_;
  int max_depth_;
  double eps_;
  const PointSubsurface* points_;
};

Surface Integrator::surface(const RayHit& h, const Vec3& d, bool face_ray) const {
  const Mesh& m = s_.meshes[h.mesh];
  const auto& tri = m.triangles[h.prim];
  const double b0 = 1 - h.b1 - h.b2;
  const Vec3 &p0 = m.position[tri[0]], &p1 = m.position[tri[1]], &p2 = m.position[tri[2]];
  Surface x;
  x.p = p0 * b0 + p1 * h.b1 + p2 * h.b2;
  x.ng = normalize(cross(p1 - p0, p2 - p0));
  if (!m.normal.empty()) {
    x.ns = normalize(m.normal[tri[0]] * b0 + m.normal[tri[1]] * h.b1 + m.normal[tri[2]] * h.b2);
    if (dot(x.ng, x.ns) < 0) x.ng = -x.ng;  // winding may disagree with the normals
  } else {
    x.ns = x.ng;
  }
  // Two-sided: face the incoming ray (single-sided quads, meshes seen from inside).
  if (face_ray && dot(x.ng, d) > 0) {
    x.ng = -x.ng;
    x.ns = -x.ns;
  }
  if (!m.uv.empty()) {
    x.has_uv = true;
    x.uv = {m.uv[tri[0]].x * b0 + m.uv[tri[1]].x * h.b1 + m.uv[tri[2]].x * h.b2,
            m.uv[tri[0]].y * b0 + m.uv[tri[1]].y * h.b1 + m.uv[tri[2]].y * h.b2};
  }
  x.mat = &s_.materials[m.material];
  x.mesh = h.mesh;
  return x;
}

bool Integrator::visible(const Vec3& p, const Vec3& n, const Vec3& wi, double dist) const {
  const Vec3 o = offset(p, n, wi);
  const double t_max = std::isinf(dist) ? kInf : dist * (1 - 1e-4) - eps_;
  return t_max > eps_ && !a_.occluded(o, wi, 0.0, t_max);
}

bool Integrator::hit_area_light(const Vec3& o, const Vec3& n, const Vec3& d, double t_max, Rgb3* Le,
                                std::size_t* index, double* pdf) const {
  const Light* nearest = nullptr;
  double best = t_max;
  for (const Light& l : s_.lights) {
    double t = kInf;
    if (l.intersect(o, d, &t) && t < best) {
      best = t;
      nearest = &l;
    }
  }
  if (!nearest) return false;
  *index = static_cast<std::size_t>(nearest - s_.lights.data());
  *Le = nearest->Le();
  *pdf = nearest->pdf(o, n, d);
  return true;
}

template <class Shading, class F, class P>
typename Shading::Value Integrator::direct(const Shading& sh, const Vec3& p, const Vec3& ns, const Vec3& ng, Sampler& rng,
                                           F f, P pdf) const {
  typename Shading::Value L{};
  const auto add = [&](const auto& light, std::size_t index) {
    const Vec2 u = rng.uniform2();
    const LightSample ls = light.sample(p, ns, u);
    if (!(ls.pdf > 0) || ls.L.is_black()) return;
    if (dot(ls.wi, ng) <= 0) return;
    const double fc = f(ls.wi);
    if (!(fc > 0) || !visible(p, ng, ls.wi, ls.dist)) return;
    const double w = ls.delta ? 1.0 : power_heuristic(ls.pdf, pdf(ls.wi));
    L += sh.emitted(ls.L, index) * (fc * w / ls.pdf);
  };
  for (std::size_t i = 0; i < s_.lights.size(); ++i) add(s_.lights[i], i);
  if (!s_.environment.black()) add(s_.environment, s_.lights.size());
  return L;
}

// The points x_i where light enters for light leaving at x_o (King et al. 2013): at the camera
// vertex the BSSRDF's probe set (a normal probe per channel and a tangent one, multi-sample
// MIS), deeper one probe of a random axis and channel (one-sample MIS); every surface point of
// the same material on a probe (up to kMaxHits) is an entry point with its weight.
template <class Shading>
int Integrator::sample_entries(const Surface& xo, const typename Shading::Bssrdf& bssrdf, Sampler& rng, bool probe_set,
                               Entry<typename Shading::Value>* out) const {
  constexpr int N = Shading::kChannels;
  int n = 0;
  const int probes = probe_set ? Shading::Bssrdf::kSetProbes : 1;
  for (int j = 0; j < probes; ++j) {
    ProbeSegment seg;
    if (probe_set) {
      const double u_a = j == N ? rng.uniform() : 0.0;
      const Vec2 u = rng.uniform2();
      if (!bssrdf.sample_set_probe(j, u_a, u.x, u.y, &seg)) continue;
    } else {
      const double u_axis = rng.uniform(), u_channel = rng.uniform();
      const Vec2 u = rng.uniform2();
      if (!bssrdf.sample_probe(u_axis, u_channel, u.x, u.y, &seg)) continue;
    }
    double t = 0;
    for (int count = 0; count < kMaxHits; ++count) {
      RayHit h;
      if (!a_.intersect(seg.start, seg.dir, t, seg.length, &h)) break;
      t = h.t + std::max(eps_, 1e-7 * seg.length);
      if (s_.meshes[h.mesh].material == s_.meshes[xo.mesh].material) {
        auto& e = out[n];
        e.x = surface(h, seg.dir, false);
        e.slot = j * kMaxHits + count;
        double w[N];
        if (probe_set ? bssrdf.probe_set_weight(j, e.x.p, e.x.ng, w) : bssrdf.probe_weight(e.x.p, e.x.ng, 1, w)) {
          e.weight = Shading::from(w);
          ++n;
        }
      }
      if (t >= seg.length) break;
    }
  }
  return n;
}

namespace {
RayHit hit_of(const SurfaceSample& at) {
  RayHit h;
  h.mesh = at.mesh;
  h.prim = at.prim;
  h.b1 = at.b1;
  h.b2 = at.b2;
  return h;
}
}  // namespace

Vec3 Integrator::normal_at(const SurfaceSample& at) const { return surface(hit_of(at), {}, false).ns; }

Rgb3 Integrator::entry_irradiance(const SurfaceSample& at, std::uint64_t seed, std::uint64_t index, int samples,
                                   Vec3* position, Vec3* normal) const {
  Surface x = surface(hit_of(at), {}, false);  // the mesh's own (outward) orientation, as entry points
  *position = x.p;
  *normal = x.ns;
  Rgb3 E;
  for (int j = 0; j < samples; ++j) {
    Sampler rng(Rng::for_sample(seed, index, static_cast<std::uint64_t>(j)));
    const TranslucentMaterial& t = *x.mat->translucent();
    const TranslucentMaterial& m = t.has_maps() && x.has_uv ? t.node_at(x.uv.x, x.uv.y, rng.uniform()) : t;
    const Bssrdf bssrdf(m.profile, m.rho_s, m.specular_albedo.get(), x.p, x.ns, s_.mm_per_unit);
    E += direct(RgbShading{}, x.p, x.ns, x.ng, rng, [&](const Vec3& wi) { return bssrdf.f_entry_cos(dot(wi, x.ns)); },
                [&](const Vec3& wi) { return pdf_cosine_hemisphere(dot(wi, x.ns)); });
    const Vec3 wi_l = sample_cosine_hemisphere(rng.uniform2());
    const Vec3 wi = Frame::from_normal(x.ns).to_world(wi_l);
    if (dot(wi, x.ng) <= 0) continue;
    // f cos / pdf = F_t(theta_i), as the probe path's continuation from x_i.
    E += bssrdf.F_t(wi_l.z) * Li(offset(x.p, x.ng, wi), wi, rng, RgbShading{}, nullptr, {1, wi_l.z / kPi, false, x.ns});
  }
  return E / static_cast<double>(samples);
}

template <class Shading>
typename Shading::Value Integrator::Li(Vec3 o, Vec3 d, Sampler& rng, const Shading& sh, bool* translucent,
                                       const PathStart& start) const {
  using Value = typename Shading::Value;
  Value L{}, beta = Shading::one();
  PathState path{o, d, start.prev_pdf, start.prev_delta, start.prev_n};
  for (int depth = start.depth;; ++depth) {
    RayHit h;
    const bool hit = a_.intersect(path.o, path.d, eps_, kInf, &h);
    const double t_hit = hit ? h.t : kInf;
    {
      Rgb3 Le;
      std::size_t light = 0;
      double lpdf = 0;
      if (hit_area_light(path.o, path.prev_n, path.d, t_hit, &Le, &light, &lpdf)) {
        const double w = path.prev_delta ? 1.0 : power_heuristic(path.prev_pdf, lpdf);
        L += beta * sh.emitted(Le, light) * w;
        break;
      }
    }
    if (!hit) {
      if (!s_.environment.black()) {
        const double lpdf = s_.environment.pdf(path.o, path.prev_n, path.d);
        const double w = path.prev_delta ? 1.0 : power_heuristic(path.prev_pdf, lpdf);
        L += beta * sh.emitted(s_.environment.radiance(path.d), s_.lights.size()) * w;
      }
      break;
    }
    if (depth >= max_depth_) break;
    if (depth <= kBlockDepths) rng.start_block(static_cast<std::uint32_t>(depth * kBlocksPerDepth));
    const Surface x = surface(h, path.d);
    if (depth == 0 && translucent) *translucent = x.mat->translucent() != nullptr;
    if (!std::visit([&](const auto& m) { return vertex(m, x, depth, rng, sh, L, beta, path); }, x.mat->type)) break;
    // Russian roulette after three bounces (unbiased: survivors are reweighted).
    if (depth >= 3) {
      const double q = std::min(0.95, beta.max());
      if (!(q > 0) || rng.uniform() >= q) break;
      beta *= 1.0 / q;
    }
  }
  return L;
}

template <class Shading>
bool Integrator::vertex(const DiffuseMaterial& m, const Surface& x, int, Sampler& rng, const Shading& sh,
                        typename Shading::Value& L, typename Shading::Value& beta, PathState& path) const {
  using Value = typename Shading::Value;
  const Value albedo = sh.reflectance(m.albedo_map && x.has_uv ? m.albedo_map->lookup(x.uv.x, x.uv.y) : m.albedo);
  const auto lambert = [&](const Vec3& wi) { return std::max(0.0, dot(wi, x.ns)) / kPi; };
  L += beta * albedo * direct(sh, x.p, x.ns, x.ng, rng, lambert, lambert);
  const Frame f = Frame::from_normal(x.ns);
  const Vec3 wi = f.to_world(sample_cosine_hemisphere(rng.uniform2()));
  if (dot(wi, x.ng) <= 0) return false;
  beta *= albedo;
  path.prev_pdf = dot(wi, x.ns) / kPi;
  path.prev_delta = false;
  path.prev_n = x.ns;
  path.o = offset(x.p, x.ng, wi);
  path.d = wi;
  return true;
}

template <class Shading>
bool Integrator::vertex(const TranslucentMaterial& material, const Surface& x, int depth, Sampler& rng,
                        const Shading& sh, typename Shading::Value& L, typename Shading::Value& beta,
                        PathState& path) const {
  using Value = typename Shading::Value;
  constexpr int N = Shading::kChannels;
  const TranslucentMaterial& m =
      material.has_maps() && x.has_uv ? material.node_at(x.uv.x, x.uv.y, rng.uniform()) : material;
  const Vec3 wo = -path.d;
  const auto bssrdf = sh.bssrdf(m, x.p, x.ns, s_.mm_per_unit);
  const Frame& f = bssrdf.frame();
  const Vec3 wo_l = f.to_local(wo);
  const double cos_o = std::max(wo_l.z, 1e-4);
  const TorranceSparrow lobe(m.rho_s, m.roughness, m.eta);
  // Surface term: direct light with MIS.
  const Vec3 wo_c{wo_l.x, wo_l.y, cos_o};
  if (m.rho_s > 0) {
    L += beta * direct(sh, x.p, x.ns, x.ng, rng,
                       [&](const Vec3& wi) { const Vec3 l = f.to_local(wi); return lobe.f(wo_c, l) * l.z; },
                       [&](const Vec3& wi) { return lobe.pdf(wo_c, f.to_local(wi)); });
  }
  // Subsurface term: entry points x_i (one probe per channel, every candidate), direct light
  // at each with MIS; the path continues from one of them, picked by its weight.
  const double Ft_o = bssrdf.F_t(cos_o);
  Value tex = Shading::one();
  if (m.albedo_map && x.has_uv) tex = sh.texture(m, m.albedo_map->lookup(x.uv.x, x.uv.y));
  const Value beta_o = beta * tex * Ft_o;
  constexpr int kMaxEntries = (N + 1) * kMaxHits;
  Entry<Value> entries[kMaxEntries];
  int n_entries = 0;
  const std::size_t mat_index = s_.meshes[x.mesh].material;
  if (points_ && !points_->cloud[mat_index].empty()) {
    // From the cloud (RGB only; render() refuses points with spectral rendering): the whole
    // subsurface term (its points' irradiance holds every bounce); the path goes on through
    // the surface term only.
    if constexpr (std::is_same_v<Shading, RgbShading>) {
      const PointCloud& cloud = points_->cloud[mat_index];
      Rgb3 M;
      if (!(points_->h > 0 && points_->cache[mat_index].interpolated_exitance(x.p, points_->h, &M)))
        M = cloud.radiant_exitance(x.p, points_->kernel.at(&m), points_->max_solid_angle, &x.ns);
      L += beta_o * M;
    }
  } else {
    n_entries = sample_entries<Shading>(x, bssrdf, rng, depth == 0, entries);
  }
  const bool entered = n_entries > 0;
  Value beta_ss;
  Surface xi;
  if (entered) {
    double total = 0, pick_w[kMaxEntries];
    for (int k = 0; k < n_entries; ++k) {
      const auto& e = entries[k];
      if (depth <= kBlockDepths) rng.start_block(static_cast<std::uint32_t>(depth * kBlocksPerDepth + 1 + e.slot));
      L += beta_o * e.weight * direct(sh, e.x.p, e.x.ns, e.x.ng, rng,
                                      [&](const Vec3& wi) { return bssrdf.f_entry_cos(dot(wi, e.x.ns)); },
                                      [&](const Vec3& wi) { return pdf_cosine_hemisphere(dot(wi, e.x.ns)); });
      double sum_abs = 0;
      for (int c = 0; c < N; ++c) sum_abs += std::abs(e.weight[c]);
      pick_w[k] = sum_abs + 1e-12;
      total += pick_w[k];
    }
    if (depth <= kBlockDepths) rng.start_block(static_cast<std::uint32_t>(depth * kBlocksPerDepth + kBlocksPerDepth - 1));
    // One entry carries the path on: picked in proportion to its weight, divided by that.
    double u = rng.uniform() * total;
    int k = 0;
    while (k + 1 < n_entries && u >= pick_w[k]) u -= pick_w[k++];
    xi = entries[k].x;
    beta_ss = beta_o * entries[k].weight * (total / pick_w[k]);
  }
  // Continue with one of the two terms, chosen by their albedo at w_o.
  const double a_spec = bssrdf.rho_dr(cos_o);
  const double a_ss = entered ? (1 - a_spec) * std::max(1e-3, m.R_d.average()) : 0.0;
  const double p_spec = a_spec + a_ss > 0 ? a_spec / (a_spec + a_ss) : 0.0;
  if (rng.uniform() < p_spec) {
    Vec3 wi_l;
    double pdf = 0;
    if (!lobe.sample({wo_l.x, wo_l.y, cos_o}, rng.uniform2(), &wi_l, &pdf) || pdf <= 0) return false;
    const Vec3 wi = f.to_world(wi_l);
    if (dot(wi, x.ng) <= 0) return false;
    beta *= lobe.f({wo_l.x, wo_l.y, cos_o}, wi_l) * wi_l.z / (pdf * p_spec);
    path.prev_pdf = pdf;
    path.prev_delta = false;
    path.prev_n = x.ns;
    path.o = offset(x.p, x.ng, wi);
    path.d = wi;
  } else {
    if (!entered || p_spec >= 1) return false;
    const Frame fi = Frame::from_normal(xi.ns);
    const Vec3 wi_l = sample_cosine_hemisphere(rng.uniform2());
    const Vec3 wi = fi.to_world(wi_l);
    if (dot(wi, xi.ng) <= 0) return false;
    // f cos / pdf = F_t(theta_i) / pi x cos / (cos / pi).
    beta = beta_ss * (bssrdf.F_t(wi_l.z) / (1 - p_spec));
    path.prev_pdf = wi_l.z / kPi;
    path.prev_delta = false;
    path.prev_n = xi.ns;
    path.o = offset(xi.p, xi.ng, wi);
    path.d = wi;
  }
  return true;
}

}  // namespace

namespace {

// Irradiance rounds per point of the cloud (next-event estimation to every light and one path
// each): the profile averages the points' noise over its footprint (head, 256 x 256, spacing
// 0.5 mm, near-field mean below: E = 0.0281, 0.0238, 0.0200 with 4, 8, 16 rounds; docs/renderer.md).
constexpr int kPointIrradianceSamples = 16;
constexpr double kMaxPoints = 5e7;
// Radii in units of the spacing sqrt(A) (measured on the head, docs/renderer.md): the disk of
// the near-field kernel, 2 sqrt(A / pi) (twice the disk a point stands for: the kernel must be
// wider than the gaps between points, or the sum ripples with the points' positions where the
// profile is sharp, blue above all), the near radius within which the points facing the same
// way count as a kernel-weighted mean, three times the kernel's disk (without that mean the sum
// carries the cloud's uneven density: head at spacing 0.5 mm, 64 spp, 16 rounds: E = 0.047 as
// a plain sum with a 3 x disk, 0.020 with the mean within 2 disks, 0.0186 with the normal test,
// 0.0178 within 3 disks, 0.0179 within 4), and the exitance cache's interpolation radius (1.5
// blurred: E 0.164 -> 0.183 on the default scene).
constexpr double kDiskRadius = 2.0 / 1.7724538509055159;  // x sqrt(A)
constexpr double kNearRadius = 3.0;                        // x the kernel's disk radius
constexpr double kCacheRadius = 1.0;

// Pass 1 of the point-based subsurface term: the points, their irradiance (in parallel, each
// point with its own random streams: the same cloud for any thread count), a cloud per
// translucent material and the near-field kernel of every translucent material and map node.
PointSubsurface build_point_subsurface(const SceneData& s, const Integrator& integ, const RenderSettings& settings,
                                       tbb::task_arena& arena) {
  const double spacing = settings.point_spacing > 0 ? settings.point_spacing : s.point_spacing;  // [mm]
  const double solid_angle = settings.point_solid_angle >= 0 ? settings.point_solid_angle : s.point_solid_angle;
  if (!(spacing > 0 && std::isfinite(spacing)))
    throw InputError("point-spacing = " + format_number(spacing) + " is out of range: must be > 0 mm");
  if (!(solid_angle >= 0 && std::isfinite(solid_angle)))
    throw InputError("point-solid-angle = " + format_number(solid_angle) + " is out of range: must be >= 0 sr");
  const double mm2 = s.mm_per_unit * s.mm_per_unit;
  const double area_mm2 = translucent_area(s) * mm2;
  const double n = std::ceil(area_mm2 / (spacing * spacing));
  if (n > kMaxPoints)
    throw InputError("point-spacing = " + format_number(spacing) + " mm is out of range: it needs " + format_number(n) +
                     " points over the scene's " + format_number(area_mm2) + " mm^2 of translucent surface, at most " +
                     format_number(kMaxPoints) + " are allowed (use a larger spacing)");
  PointSubsurface out;
  out.max_solid_angle = solid_angle;
  out.spacing = spacing;
  out.h = kCacheRadius * spacing / s.mm_per_unit;
  out.cloud.resize(s.materials.size());
  double area = 0;  // [scene units^2] per point
  const std::vector<SurfaceSample> at = distribute_points(s, static_cast<std::size_t>(n), &area);
  std::vector<SurfaceSample> cache_at;
  if (out.h > 0) cache_at = distribute_points(s, static_cast<std::size_t>(n), &area, 1);
  out.cache.resize(s.materials.size());
  std::vector<Vec3> position(at.size()), normal(at.size());
  std::vector<Rgb3> EA(at.size());
  const double A = area * mm2;  // [mm^2]
  const std::uint64_t seed = settings.seed ^ 0x70c1a5e5d0u;  // streams apart from the camera's
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, at.size(), 256), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t i = r.begin(); i < r.end(); ++i) {
        if (util::cancel::requested()) return;
        EA[i] = integ.entry_irradiance(at[i], seed, i, kPointIrradianceSamples, &position[i], &normal[i]) * A;
      }
    });
  });
  util::cancel::check();
  // The points are sorted by mesh: one cloud per material over its meshes' points.
  for (std::size_t mat = 0; mat < s.materials.size(); ++mat) {
    if (!s.materials[mat].translucent()) continue;
    std::vector<Vec3> p, nrm;
    std::vector<Rgb3> ea;
    for (std::size_t i = 0; i < at.size(); ++i)
      if (s.meshes[at[i].mesh].material == mat) {
        p.push_back(position[i]);
        nrm.push_back(normal[i]);
        ea.push_back(EA[i]);
      }
    out.cloud[mat] = PointCloud(std::move(p), std::move(ea), A, s.mm_per_unit, std::move(nrm));
    const double a = kDiskRadius * std::sqrt(A);  // [mm]
    const TranslucentMaterial& m = *s.materials[mat].translucent();
    out.kernel.emplace(&m, NearFieldKernel(&m.profile, a, kNearRadius * a));
    for (const TranslucentMaterial& node : m.nodes) out.kernel.emplace(&node, NearFieldKernel(&node.profile, a, kNearRadius * a));
    // The exitance cache (not with parameter maps: there the profile depends on the shading
    // point's node).
    if (out.h > 0 && !m.has_maps()) {
      std::vector<Vec3> cp, cn;
      for (const SurfaceSample& x : cache_at)
        if (s.meshes[x.mesh].material == mat) {
          cp.push_back(position_of(s, x));
          cn.push_back(integ.normal_at(x));
        }
      const std::size_t n_cache = cp.size();
      PointCloud cache(std::move(cp), std::vector<Rgb3>(n_cache), A, s.mm_per_unit, std::move(cn));
      const PointCloud& cloud = out.cloud[mat];
      const NearFieldKernel& k = out.kernel.at(&m);
      std::vector<Rgb3> M(cache.size());
      arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, M.size(), 256), [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t i = r.begin(); i < r.end(); ++i)
            M[i] = cloud.radiant_exitance(cache.positions()[i], k, solid_angle, &cache.normals()[i]);
        });
      });
      cache.set_exitance(std::move(M));
      out.cache[mat] = std::move(cache);
    }
  }
  return out;
}

// Image size and samples per pixel of a render: the settings', else the scene's.
struct Extent {
  int W, H, spp;
};
Extent extent(const SceneData& s, const RenderSettings& settings) {
  return {settings.width > 0 ? settings.width : s.camera.width,
          settings.height > 0 ? settings.height : s.camera.height, settings.spp > 0 ? settings.spp : s.spp};
}
}  // namespace

RenderCost render_cost(const Scene& scene, const RenderSettings& settings) {
  const Extent e = extent(scene.impl().data, settings);
  const double pixels = static_cast<double>(e.W) * e.H;
  const double spp = settings.target_error > 0 ? (settings.spp > 0 ? settings.spp : kAdaptiveMaxSpp) : e.spp;
  // Per pixel: the sums and sums of squares (Rgb3 of doubles), the sample and skin counts, the
  // active flag, the mask and the image (3 floats).
  return {pixels * spp, pixels * static_cast<double>(2 * sizeof(Rgb3) + 2 * sizeof(std::uint32_t) + 2 + 3 * sizeof(float))};
}

double relative_rms_error(const Image& image, const Image& reference, const std::vector<std::uint8_t>& mask) {
  if (image.width != reference.width || image.height != reference.height)
    throw InputError("reference: its size " + std::to_string(reference.width) + "x" + std::to_string(reference.height) +
                     " differs from the image's " + std::to_string(image.width) + "x" + std::to_string(image.height));
  if (mask.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height))
    throw InputError("reference: the skin mask does not match the image");
  double se = 0, ref = 0;
  std::size_t n = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      if (!mask[static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x)]) continue;
      const Rgb3 a = image.at(x, y), b = reference.at(x, y);
      const Rgb3 d = a - b;
      se += d.r * d.r + d.g * d.g + d.b * d.b;
      ref += b.r + b.g + b.b;
      ++n;
    }
  if (n == 0) throw InputError("reference: the image has no skin pixels to compare");
  return std::sqrt(se / (3.0 * static_cast<double>(n))) / (ref / (3.0 * static_cast<double>(n)));
}

Image render(const Scene& scene, const RenderSettings& settings, RenderStats* stats, const Progress& progress) {
  const SceneData& s = scene.impl().data;
  const Accel& accel = *scene.impl().accel;
  const Extent e = extent(s, settings);
  const bool adaptive = settings.target_error > 0;
  // (named copies: lambdas below capture them)
  const int W = e.W, H = e.H, spp = adaptive ? (settings.spp > 0 ? settings.spp : kAdaptiveMaxSpp) : e.spp;
  const int max_depth = settings.max_depth >= 0 ? settings.max_depth : s.max_depth;
  if (W <= 0 || H <= 0 || W > 16384 || H > 16384)
    throw InputError("resolution = " + std::to_string(W) + "x" + std::to_string(H) + " is out of range: each side must be in [1, 16384]");
  if (spp <= 0 || spp > 1000000) throw InputError("spp = " + std::to_string(spp) + " is out of range: [1, 1000000]");
  if (settings.threads < 0) throw InputError("threads = " + std::to_string(settings.threads) + " is out of range: must be >= 0 (0 = all)");
  require_non_negative("time-budget", settings.time_budget, "s");
  if (!(settings.target_error >= 0 && settings.target_error < 1))
    throw InputError("target-error = " + std::to_string(settings.target_error) +
                     " is out of range: must be in [0, 1) (a relative error; 0 = off)");
  if (s.spectral && (settings.subsurface == RenderSettings::Subsurface::points ||
                     (settings.subsurface == RenderSettings::Subsurface::scene && s.subsurface_points)))
    throw InputError("subsurface = points is not available with spectral rendering (its cloud holds RGB irradiance): use "
                     "subsurface = probes, or RGB rendering");
  tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
  const auto t0 = std::chrono::steady_clock::now();
  const bool use_points = settings.subsurface == RenderSettings::Subsurface::points ||
                          (settings.subsurface == RenderSettings::Subsurface::scene && s.subsurface_points);
  PointSubsurface points;
  if (use_points) points = build_point_subsurface(s, Integrator(s, accel, max_depth), settings, arena);
  const Integrator integ(s, accel, max_depth, use_points ? &points : nullptr);
  const double point_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // Spectral rendering: each light's emission spectrum, then the environment's (D65-referred RGB).
  std::vector<SpectralEmission> emission;
  if (s.spectral) {
    for (const Light& l : s.lights) emission.emplace_back(l.illuminant());
    emission.emplace_back(s.environment.illuminant);
    for (const Material& m : s.materials)
      SKIN_ASSERT(!m.translucent() || m.translucent()->spectral, "spectral render without the spectral profiles");
  }
  const bool spectral = s.spectral;

  const PinholeCamera camera(s.camera, W, H);
  const std::size_t pixels = static_cast<std::size_t>(W) * static_cast<std::size_t>(H);
  Film film(pixels);
  SamplePasses passes(settings, spp, pixels);
  std::atomic<std::uint64_t> invalid{0};
  constexpr int kTile = 16;
  const int tiles_x = (W + kTile - 1) / kTile, tiles_y = (H + kTile - 1) / kTile;
  const std::uint64_t total_work =
      static_cast<std::uint64_t>(tiles_x) * tiles_y * static_cast<std::uint64_t>(passes.count());
  std::atomic<std::uint64_t> work_done{0};
  std::mutex progress_mutex;
  int done = 0;
  while (done < spp) {
    const int s0 = done, s1 = passes.end(done);
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range2d<int>(0, tiles_y, 1, 0, tiles_x, 1), [&](const tbb::blocked_range2d<int>& r) {
        for (int ty = r.rows().begin(); ty < r.rows().end(); ++ty)
          for (int tx = r.cols().begin(); tx < r.cols().end(); ++tx) {
            for (int y = ty * kTile; y < std::min(H, (ty + 1) * kTile); ++y)
              for (int x = tx * kTile; x < std::min(W, (tx + 1) * kTile); ++x) {
                if (util::cancel::requested()) return;  // thrown below, after the pass
                const auto pixel = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(W) + static_cast<std::uint64_t>(x);
                if (!passes.active(pixel)) continue;
                Film::Pixel acc = film.pixel(pixel);
                for (int si = s0; si < s1; ++si) {
                  // Even and odd samples: two replicates, each its own scrambled sequence.
                  Sampler rng(settings.seed, 2 * pixel + static_cast<std::uint64_t>(si & 1),
                              static_cast<std::uint32_t>(si >> 1));
                  const Vec2 jitter = rng.uniform2();
                  const Vec3 dir = camera.direction((x + jitter.x) / W, (y + jitter.y) / H);
                  bool translucent = false;
                  Rgb3 c;
                  if (spectral) {
                    const SpectralShading sh{&emission, SampledWavelengths::hero(rng.uniform())};
                    c = film_srgb_linear(integ.Li(camera.eye(), dir, rng, sh, &translucent), sh.wl);
                  } else {
                    c = integ.Li(camera.eye(), dir, rng, RgbShading{}, &translucent);
                  }
                  acc.skin_hits += translucent ? 1 : 0;
                  if (std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b)) {
                    acc.sum += c;
                    acc.sum_sq += c * c;
                    if (si & 1) acc.sum_odd += c;
                  } else {
                    invalid.fetch_add(1, std::memory_order_relaxed);
                  }
                }
                film.set(pixel, acc, static_cast<std::uint32_t>(s1));
              }
            const std::uint64_t w = work_done.fetch_add(1, std::memory_order_relaxed) + 1;
            if (progress) {
              const std::lock_guard lock(progress_mutex);
              progress(std::min(1.0, static_cast<double>(w) / static_cast<double>(total_work)));
            }
          }
      });
    });
    util::cancel::check();
    done = s1;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (settings.time_budget > 0 && elapsed >= settings.time_budget) break;
    if (passes.converged(film, done)) break;
  }
  Image img = film.image(W, H);
  if (stats) {
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    stats->spp_done = done;
    stats->invalid_samples = invalid.load();
    stats->point_seconds = point_seconds;
    stats->points = 0;
    for (const PointCloud& c : points.cloud) stats->points += c.size();
    stats->point_spacing = stats->points > 0 ? points.spacing : 0.0;
    film.fill(stats);
  }
  return img;
}

}  // namespace skin::render
