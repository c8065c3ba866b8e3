// End-to-end renders with answers known in closed form.
#include <gtest/gtest.h>

#include <cmath>

#include "skin/model/skin_model.hpp"
#include "skin/render/scene.hpp"

namespace skin::render {
namespace {

struct Stats {
  Rgb3 mean, stderr_;  // mean over pixels and its standard error
};

Stats pixel_stats(const Image& img) {
  Rgb3 s, s2;
  const int n = img.width * img.height;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const Rgb3 c = img.at(x, y);
      s += c;
      s2 += c * c;
    }
  Stats st;
  st.mean = s / n;
  for (int c = 0; c < 3; ++c)
    st.stderr_[c] = std::sqrt(std::max(0.0, s2[c] / n - st.mean[c] * st.mean[c]) / n);
  return st;
}

// A flat slab seen from straight above, filling the view, under a uniform environment of unit
// radiance; `material` is the JSON of the slab's material.
std::string slab_scene(const std::string& material, int depth = 1) {
  return R"({ "camera": {"eye":[0,100,0], "look_at":[0,0,0], "up":[0,0,-1], "fov": 10, "resolution":[64,64]},
  "materials": {"m": )" + material + R"(},
  "objects": [{"quad": {"corner":[-2000,0,2000], "edge_u":[4000,0,0], "edge_v":[0,0,-4000]}, "material":"m"}],
  "environment": {"radiance": 1}, "render": {"spp": 32, "max_depth": )" + std::to_string(depth) + "} }";
}

TEST(KnownAnswer, SkinSlabWithoutSpecularIsRdColour) {
  // With rho_s = 0 nothing is reflected at the surface, F_t = 1, and the subsurface term of a
  // semi-infinite flat slab under uniform unit radiance is L_o = (1/pi) int R(r) dA int cos dw
  // = R_d: the pixel colour is the linear sRGB colour of R_d, which `skin color` reports.
  const Scene scene = Scene::parse(slab_scene(R"({"type":"skin","preset":"caucasian","rho_s":0})"), "", "slab");
  RenderSettings rs;
  rs.seed = 7;
  const Stats st = pixel_stats(render(scene, rs));
  SkinParameters p = find_preset("caucasian").parameters;
  p.oiliness = 0;
  const auto expected = skin_spectrum(p).color.srgb_linear;
  for (int c = 0; c < 3; ++c) {
    SCOPED_TRACE(c);
    EXPECT_NEAR(st.mean[c], expected[c], 0.01 * expected[c]) << st.mean << " stderr " << st.stderr_;
  }
}

}  // namespace
}  // namespace skin::render
