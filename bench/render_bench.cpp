// Renderer benchmarks: the hot paths one by one (BSSRDF probe sampling, its MIS pdf and weight;
// the profile table; the surface term and its rho_dr table; light sampling), camera samples per
// second on the head scene (skipped without the mesh), and on the default scene skin against
// diffuse side by side (the same geometry, lights and path depth; only the materials differ),
// and setup costs. Each micro-benchmark runs a batch of 1024 calls on precomputed random numbers
// so that the generator is not what is measured; items = calls.
#include <benchmark/benchmark.h>

#include <array>
#include <filesystem>
#include <vector>

#include "lights.hpp"
#include "scene_data.hpp"
#include "skin/render/bssrdf.hpp"
#include "skin/render/scene.hpp"

namespace {

using namespace skin::render;  // NOLINT(google-build-using-namespace)
constexpr int kBatch = 1024;

// The caucasian preset's material (profiles, specular albedo), built once.
const TranslucentMaterial& caucasian() {
  static const TranslucentMaterial m = [] {
    MaterialDescription d = skin_description(skin::physics::find_preset("caucasian").parameters);
    d.name = "caucasian";
    return build_translucent(d);
  }();
  return m;
}

std::vector<double> uniforms(std::size_t n, std::uint64_t seed) {
  Rng rng(seed, 7);
  std::vector<double> u(n);
  for (auto& x : u) x = rng.uniform();
  return u;
}

// Runs f(i) for i in [0, kBatch) per iteration; items = calls.
template <class F>
void batch(benchmark::State& state, F&& f) {
  for (auto _ : state)
    for (int i = 0; i < kBatch; ++i) f(static_cast<std::size_t>(i));
  state.SetItemsProcessed(state.iterations() * kBatch);
}

Bssrdf flat_bssrdf() {
  const TranslucentMaterial& m = caucasian();
  // A flat exit point at the origin, normal +z, 1 mm per unit.
  return Bssrdf(m.profile, m.rho_s, m.specular_albedo.get(), {0, 0, 0}, {0, 0, 1}, 1.0);
}

// Entry points on the plane z = 0 at radii drawn from the red profile (where probes land).
std::vector<Vec3> entry_points() {
  const Bssrdf b = flat_bssrdf();
  const auto u = uniforms(2 * kBatch, 3);
  std::vector<Vec3> p(kBatch);
  for (int i = 0; i < kBatch; ++i) {
    const double r = b.sample_r(0, u[2 * i]), phi = 2 * kPi * u[2 * i + 1];
    p[static_cast<std::size_t>(i)] = {r * std::cos(phi), r * std::sin(phi), 0};
  }
  return p;
}

void BM_ProbeSample(benchmark::State& state) {
  const Bssrdf b = flat_bssrdf();
  const auto u = uniforms(4 * kBatch, 1);
  batch(state, [&](std::size_t i) {
    ProbeSegment seg;
    const double* q = &u[4 * i];
    benchmark::DoNotOptimize(b.sample_probe(q[0], q[1], q[2], q[3], &seg));
    benchmark::DoNotOptimize(seg);
  });
}
BENCHMARK(BM_ProbeSample);

void BM_ProbePdf(benchmark::State& state) {
  const Bssrdf b = flat_bssrdf();
  const auto p = entry_points();
  batch(state, [&](std::size_t i) { benchmark::DoNotOptimize(b.pdf_probe(p[i], {0, 0, 1})); });
}
BENCHMARK(BM_ProbePdf);

void BM_ProbeWeight(benchmark::State& state) {
  const Bssrdf b = flat_bssrdf();
  const auto p = entry_points();
  batch(state, [&](std::size_t i) {
    Rgb3 w;
    benchmark::DoNotOptimize(b.probe_weight(p[i], {0, 0, 1}, 1, &w));
    benchmark::DoNotOptimize(w);
  });
}
BENCHMARK(BM_ProbeWeight);

// The probe set's weight of an entry point found by probe j (its densities per axis and channel,
// the channel-weighted MIS sum, R of three channels).
void BM_ProbeSetWeight(benchmark::State& state) {
  const Bssrdf b = flat_bssrdf();
  const auto p = entry_points();
  batch(state, [&](std::size_t i) {
    double w[3];
    benchmark::DoNotOptimize(b.probe_set_weight(static_cast<int>(i % 3), p[i], {0, 0, 1}, w));
    benchmark::DoNotOptimize(w);
  });
}
BENCHMARK(BM_ProbeSetWeight);

// The quasi-random sampler: a 2D dimension (index shuffle, Sobol's two dimensions, two
// scrambles), and a 1D one; a new block every 32 calls (as the integrator does per vertex).
void BM_SamplerUniform2(benchmark::State& state) {
  Sampler s(1, 5, 37);
  batch(state, [&](std::size_t i) {
    if (i % 32 == 0) s.start_block(static_cast<std::uint32_t>(i));
    benchmark::DoNotOptimize(s.uniform2());
  });
}
BENCHMARK(BM_SamplerUniform2);

void BM_SamplerUniform(benchmark::State& state) {
  Sampler s(1, 5, 37);
  batch(state, [&](std::size_t i) {
    if (i % 32 == 0) s.start_block(static_cast<std::uint32_t>(i));
    benchmark::DoNotOptimize(s.uniform());
  });
}
BENCHMARK(BM_SamplerUniform);

// The profile table of the red channel: radius sampling (inverse CDF), its pdf, the profile.
void BM_ProfileSampleRadius(benchmark::State& state) {
  const TabulatedProfile& t = caucasian().profile[0];
  const auto u = uniforms(kBatch, 2);
  batch(state, [&](std::size_t i) { benchmark::DoNotOptimize(t.sample_radius(u[i])); });
}
BENCHMARK(BM_ProfileSampleRadius);

void BM_ProfilePdfAndEval(benchmark::State& state) {
  const TabulatedProfile& t = caucasian().profile[0];
  std::vector<double> r;
  for (double x : uniforms(kBatch, 4)) r.push_back(t.sample_radius(x));
  batch(state, [&](std::size_t i) {
    benchmark::DoNotOptimize(t.pdf_radius(r[i]));
    benchmark::DoNotOptimize(t.eval(r[i]));
  });
}
BENCHMARK(BM_ProfilePdfAndEval);

// The surface term: f_s and its pdf for sampled directions, sampling, and the rho_dr table.
void BM_MicrofacetEval(benchmark::State& state) {
  const TorranceSparrow ts(0.3, 0.35, 1.4);
  const auto u = uniforms(4 * kBatch, 5);
  std::vector<std::pair<Vec3, Vec3>> dirs;
  for (int i = 0; i < kBatch; ++i) {
    const std::size_t k = static_cast<std::size_t>(4 * i);
    const Vec3 wo = sample_uniform_sphere({u[k], u[k + 1]}), wi = sample_uniform_sphere({u[k + 2], u[k + 3]});
    dirs.push_back({{wo.x, wo.y, std::abs(wo.z)}, {wi.x, wi.y, std::abs(wi.z)}});
  }
  batch(state, [&](std::size_t i) {
    benchmark::DoNotOptimize(ts.f(dirs[i].first, dirs[i].second));
    benchmark::DoNotOptimize(ts.pdf(dirs[i].first, dirs[i].second));
  });
}
BENCHMARK(BM_MicrofacetEval);

void BM_MicrofacetSample(benchmark::State& state) {
  const TorranceSparrow ts(0.3, 0.35, 1.4);
  const auto u = uniforms(2 * kBatch, 6);
  const Vec3 wo = normalize(Vec3{0.3, 0.1, 0.9});
  batch(state, [&](std::size_t i) {
    Vec3 wi;
    double pdf = 0;
    benchmark::DoNotOptimize(ts.sample(wo, {u[2 * i], u[2 * i + 1]}, &wi, &pdf));
    benchmark::DoNotOptimize(pdf);
  });
}
BENCHMARK(BM_MicrofacetSample);

void BM_RhoDrLookup(benchmark::State& state) {
  const SpecularAlbedo& a = *caucasian().specular_albedo;
  const auto u = uniforms(kBatch, 8);
  batch(state, [&](std::size_t i) { benchmark::DoNotOptimize(a.rho_dr(u[i])); });
}
BENCHMARK(BM_RhoDrLookup);

// Light sampling from points near the origin: sample + pdf, by type (0 sphere, 1 quad).
void BM_LightSample(benchmark::State& state) {
  const Light light = state.range(0) == 0 ? Light(SphereLight{{14, 10, 16}, 2.5, {30, 27, 24}})
                                          : Light(QuadLight{{-2, 8, -2}, {4, 0, 0}, {0, 0, 4}, {10, 10, 10}});
  const auto u = uniforms(5 * kBatch, 9);
  batch(state, [&](std::size_t i) {
    const double* q = &u[5 * i];
    const Vec3 p{q[0] - 0.5, q[1] - 0.5, q[2] - 0.5};
    const LightSample s = light.sample(p, {0, 1, 0}, {q[3], q[4]});
    benchmark::DoNotOptimize(s);
    benchmark::DoNotOptimize(light.pdf(p, {0, 1, 0}, s.wi));
  });
  state.SetLabel(state.range(0) == 0 ? "sphere" : "quad");
}
BENCHMARK(BM_LightSample)->Arg(0)->Arg(1);

// Renders `scene` at w x h, 4 spp, per iteration; items = camera samples.
std::int64_t render_samples(benchmark::State& state, const Scene& scene, int w, int h, int threads) {
  RenderSettings rs;
  rs.width = w;
  rs.height = h;
  rs.spp = 4;
  rs.threads = threads;
  std::int64_t samples = 0;
  for (auto _ : state) {
    RenderStats stats;
    benchmark::DoNotOptimize(render(scene, rs, &stats));
    samples += static_cast<std::int64_t>(stats.camera_samples);
  }
  state.SetItemsProcessed(samples);
  return samples;
}

// Camera samples on examples/head.json (the Lee Perry-Smith head, three sphere lights) at
// 64 x 64, 4 spp, one thread; skipped when the mesh is absent (run from the source directory,
// the scene finds it in ../shared/data).
void BM_HeadCameraSample(benchmark::State& state) {
  const std::string path = SKIN_SOURCE_DIR "/examples/head.json";
  const std::string mesh = SKIN_SOURCE_DIR "/../shared/data/meshes/LeePerrySmith/LeePerrySmith.glb";
  if (!std::filesystem::exists(mesh)) {
    state.SkipWithError("no head mesh (../shared/data/meshes/LeePerrySmith)");
    for (auto _ : state) {
    }
    return;
  }
  render_samples(state, Scene::load(path), 64, 64, 1);
}
BENCHMARK(BM_HeadCameraSample)->Unit(benchmark::kMillisecond);

// Renders the default scene at 192 x 128, `spp` samples; threads from the argument.
void render_default(benchmark::State& state, bool diffuse) {
  SceneDescription description = SceneDescription::default_scene();
  if (diffuse) description.make_translucent_diffuse();
  const Scene scene = description.build();
  const std::int64_t samples = render_samples(state, scene, 192, 128, static_cast<int>(state.range(0)));
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(samples), benchmark::Counter::kIsRate);
}

void BM_DefaultSceneSkin(benchmark::State& state) { render_default(state, false); }
void BM_DefaultSceneDiffuse(benchmark::State& state) { render_default(state, true); }
BENCHMARK(BM_DefaultSceneSkin)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_DefaultSceneDiffuse)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The default scene at 192 x 128, 16 spp, one thread, with the subsurface term from the point
// cloud (default spacing): the time of the camera samples alone (the render's time less the
// cloud's, RenderStats::point_seconds) per sample, and the cloud's time per run beside it.
void BM_DefaultScenePointsSamples(benchmark::State& state) {
  const Scene scene = Scene::default_scene();
  RenderSettings rs;
  rs.width = 192;
  rs.height = 128;
  rs.spp = 16;
  rs.threads = 1;
  rs.subsurface = RenderSettings::Subsurface::points;
  double sample_seconds = 0, cloud_seconds = 0;
  std::int64_t samples = 0, runs = 0;
  for (auto _ : state) {
    RenderStats stats;
    benchmark::DoNotOptimize(render(scene, rs, &stats));
    sample_seconds += stats.seconds - stats.point_seconds;
    cloud_seconds += stats.point_seconds;
    samples += static_cast<std::int64_t>(stats.camera_samples);
    ++runs;
  }
  state.counters["us/sample"] = samples > 0 ? 1e6 * sample_seconds / static_cast<double>(samples) : 0.0;
  state.counters["cloud s"] = runs > 0 ? cloud_seconds / static_cast<double>(runs) : 0.0;
}
BENCHMARK(BM_DefaultScenePointsSamples)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

// Setup: four skin materials (profiles by inverse Hankel transform) and the Embree build.
void BM_DefaultSceneSetup(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(Scene::default_scene());
}
BENCHMARK(BM_DefaultSceneSetup)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
