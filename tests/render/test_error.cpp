// The renderer's error measures: the relative RMS error against a reference, the error the
// render estimates from its own samples, and adaptive sampling to a target error.
#include <gtest/gtest.h>

#include <cmath>

#include "skin/render/scene.hpp"
#include "skin/util/error.hpp"

namespace skin::render {

using skin::util::InputError;

namespace {

TEST(RenderError, RelativeRmsErrorInClosedForm) {
  Image ref(4, 2), img(4, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      ref.set(x, y, {0.5, 0.5, 0.5});
      img.set(x, y, {0.55, 0.45, 0.5});  // errors +-0.05 in two channels: RMS 0.05 sqrt(2/3)
    }
  img.set(3, 1, {9, 9, 9});  // outside the mask: ignored
  std::vector<std::uint8_t> mask(8, 1);
  mask[7] = 0;
  EXPECT_NEAR(relative_rms_error(img, ref, mask), 0.05 * std::sqrt(2.0 / 3.0) / 0.5, 1e-6);
  EXPECT_THROW(relative_rms_error(img, Image(3, 2), mask), InputError);
  EXPECT_THROW(relative_rms_error(img, ref, std::vector<std::uint8_t>(8, 0)), InputError);
}

// A skin sphere on a grey floor under a sphere light: skin pixels, the floor not.
const char* kScene = R"({ "camera": {"eye":[0,20,120], "look_at":[0,0,0], "fov": 30, "resolution":[48,36]},
  "materials": {"s": {"type":"skin","preset":"asian"}, "d": {"type":"diffuse","albedo":0.4}},
  "objects": [{"sphere": {"center":[0,0,0], "radius":20}, "material":"s"},
              {"quad": {"corner":[-100,-20,100], "edge_u":[200,0,0], "edge_v":[0,0,-200]}, "material":"d"}],
  "lights": [{"type":"sphere","center":[-50,80,60],"radius":25,"radiance":5}],
  "environment": {"radiance": 0.2}, "render": {"spp": 8, "max_depth": 3} })";

// A high-sample render of kScene: the reference the tests measure against.
struct Reference {
  Image image;
  RenderStats stats;
};
Reference render_reference(const Scene& scene, int spp, std::uint64_t seed) {
  RenderSettings rs;
  rs.spp = spp;
  rs.seed = seed;
  Reference r;
  r.image = render(scene, rs, &r.stats);
  return r;
}

TEST(RenderError, EstimatedErrorMatchesTheMeasuredOne) {
  // Independent renders (other seeds) at 16 spp against a 1024-spp reference: the measured error
  // includes the reference's own (1/64 of the variance, so x 1.008). One render's measured error
  // scatters with its rare bright paths (0.128 and 0.086 for seeds 1 and 2), and so does its
  // estimate (from the difference of the two replicates); over four renders the RMS of the
  // estimates and of the measurements agree within 15 % (observed: 0.109 and 0.110), and each
  // estimate is within a factor 1.5 of its measurement (observed: 0.83-1.30).
  const Scene scene = Scene::parse(kScene, "", "error");
  const auto [ref, ref_stats] = render_reference(scene, 1024, 99);
  RenderSettings rs;
  ASSERT_GT(ref_stats.skin_pixels, 100u);
  ASSERT_LT(ref_stats.skin_pixels, 48u * 36u / 2);  // the floor is not skin
  double est2 = 0, meas2 = 0;
  for (const std::uint64_t seed : {1u, 2u, 3u, 4u}) {
    rs.spp = 16;
    rs.seed = seed;
    RenderStats st;
    const Image img = render(scene, rs, &st);
    const double measured = relative_rms_error(img, ref, ref_stats.skin_mask) / std::sqrt(1 + 16.0 / 1024);
    EXPECT_GT(st.estimated_error, measured / 1.5) << "seed " << seed;
    EXPECT_LT(st.estimated_error, measured * 1.5) << "seed " << seed;
    EXPECT_GT(st.estimated_error, 0.005);  // a real error, not a degenerate estimate
    est2 += st.estimated_error * st.estimated_error;
    meas2 += measured * measured;
  }
  EXPECT_NEAR(std::sqrt(est2 / 4), std::sqrt(meas2 / 4), 0.15 * std::sqrt(meas2 / 4));
}

TEST(RenderError, AdaptiveSamplingReachesTheTarget) {
  const Scene scene = Scene::parse(kScene, "", "error");
  const auto [ref, ref_stats] = render_reference(scene, 2048, 5);
  RenderSettings rs;
  rs.seed = 6;
  rs.spp = 0;  // adaptive: at most 65536
  rs.target_error = 0.03;
  RenderStats st;
  const Image img = render(scene, rs, &st);
  EXPECT_LE(st.estimated_error, 0.03);
  // Measured against the reference, whose own error (estimated, 0.0060) adds in quadrature:
  // within 30 % of the target (observed: 0.0282 measured, so 0.0275 of the render's own; the
  // estimate said 0.0293).
  const double measured = relative_rms_error(img, ref, ref_stats.skin_mask);
  EXPECT_LE(std::sqrt(std::max(0.0, measured * measured - ref_stats.estimated_error * ref_stats.estimated_error)),
            1.3 * 0.03) << measured << " against a reference of error " << ref_stats.estimated_error;
  // Fewer samples than stopping every pixel at the slowest one's count: the floor and the
  // background stop after the first pass.
  EXPECT_LT(static_cast<double>(st.camera_samples), 0.7 * 48 * 36 * st.spp_done);
  // Deterministic as any render: the same image for one and two threads.
  rs.threads = 1;
  EXPECT_TRUE(render(scene, rs).rgb == img.rgb);
  rs.target_error = 1.5;
  EXPECT_THROW(render(scene, rs), InputError);
}

}  // namespace
}  // namespace skin::render
