// Scene input through the command line: bad input gives one clear line naming the file and the
// problem, exit code 2, and no output file; awkward but valid meshes render.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "scene_data.hpp"
#include "scene_impl.hpp"
#include "skin/render/image.hpp"
#include "skin/render/scene.hpp"
#include "skin_test_paths.hpp"

namespace fs = std::filesystem;

namespace skin::render {

using skin::transport::DiffusionStack;

using skin::physics::Layer;
using skin::physics::LayerStack;
using skin::physics::kInfinity;

namespace {

class SceneInput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("skin_render_input_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
  // Runs `skin render <args>` in the test directory; returns the exit code, stderr in *err.
  int run(const std::string& args, std::string* err) {
    const fs::path err_path = dir_ / "stderr.txt";
    const std::string cmd = "cd '" + dir_.string() + "' && '" SKIN_BINARY "' render " + args + " > /dev/null 2> '" + err_path.string() + "'";
    const int status = std::system(cmd.c_str());
    std::stringstream ss;
    ss << std::ifstream(err_path).rdbuf();
    *err = ss.str();
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  // Expects exit 2, one line on stderr containing every `needle`, and no out.png.
  void expect_rejected(const std::string& scene, std::initializer_list<std::string> needles) {
    std::string err;
    EXPECT_EQ(run(scene + " -o out.png --spp 1 --resolution 8x8", &err), 2) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    for (const auto& n : needles) EXPECT_NE(err.find(n), std::string::npos) << "missing '" << n << "' in: " << err;
    EXPECT_FALSE(fs::exists(dir_ / "out.png"));
  }
  std::string scene_with(const std::string& object, const std::string& material = R"({"type":"diffuse"})") {
    return R"({"camera": {"eye":[0,0,5], "look_at":[0,0,0]}, "materials": {"m": )" + material +
           R"(}, "objects": [)" + object + R"(], "environment": {"radiance": 1}})";
  }
  fs::path dir_;
};

const char* kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

TEST_F(SceneInput, SpectralNeedsSkinOrDiffuseMaterials) {
  // Layered materials are given per RGB channel: no spectrum to render, from the scene key or
  // from --spectral. A wrong type of the key, or an illuminant on an environment map, is named.
  const std::string layered = R"({"type":"layered","layers":[{"sigma_a":0.1,"sigma_s_prime":2}]})";
  std::string js = scene_with(R"({"sphere": {"center":[0,0,0], "radius":1}, "material": "m"})", layered);
  write("flag.json", js);
  std::string err;
  EXPECT_EQ(run("flag.json -o out.png --spp 1 --resolution 8x8 --spectral", &err), 2) << err;
  EXPECT_NE(err.find("material 'm' is layered"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir_ / "out.png"));
  js.insert(js.size() - 1, R"(, "render": {"spectral": true})");
  write("key.json", js);
  expect_rejected("key.json", {"key.json", "render.spectral", "material 'm' is layered"});
  std::string diffuse = scene_with(R"({"sphere": {"center":[0,0,0], "radius":1}, "material": "m"})");
  write("bad.json", diffuse.substr(0, diffuse.size() - 1) + R"(, "render": {"spectral": "yes"}})");
  expect_rejected("bad.json", {"bad.json", "spectral", "true or false"});
  const std::string env = R"("environment": {"radiance": 1})";
  write("env.json", diffuse.replace(diffuse.find(env), env.size(), R"("environment": {"map": "sky.exr", "illuminant": "A"})"));
  expect_rejected("env.json", {"env.json", "illuminant", "constant"});
}

TEST_F(SceneInput, MissingMesh) {
  write("s.json", scene_with(R"({"mesh": "nothere.obj", "material": "m"})"));
  expect_rejected("s.json", {"s.json", "nothere.obj", "not found"});
}

TEST_F(SceneInput, MissingTexture) {
  write("t.obj", kTriangleObj);
  write("s.json", scene_with(R"({"mesh": "t.obj", "material": "m"})", R"({"type":"skin","albedo_texture":"skin.jpg"})"));
  expect_rejected("s.json", {"s.json", "skin.jpg", "not found"});
}

TEST_F(SceneInput, MalformedJson) {
  write("s.json", R"({"camera": {"eye": [0,0,5], )");
  expect_rejected("s.json", {"s.json", "malformed JSON"});
}

TEST_F(SceneInput, ToneMapKey) {
  // render.tone_map: clip or filmic (the same names as --tone-map); another name is refused.
  const std::string sphere = R"({"sphere": {"center": [0, 0, 0], "radius": 1}, "material": "m"})";
  std::string scene = scene_with(sphere);
  scene.insert(1, R"("render": {"tone_map": "filmic"}, )");
  EXPECT_EQ(Scene::parse(scene, "", "s.json").tone_map(), ToneMap::filmic);
  EXPECT_EQ(Scene::parse(scene_with(sphere), "", "s.json").tone_map(), ToneMap::clip);
  std::string bad = scene_with(sphere);
  bad.insert(1, R"("render": {"tone_map": "aces"}, )");
  write("s.json", bad);
  expect_rejected("s.json", {"s.json", "render.tone_map", "'aces' is not one of clip, filmic"});
  // --tone-map overrides the scene's; an unknown name is refused by the command line.
  write("s.json", scene);
  std::string err;
  EXPECT_EQ(run("s.json -o out.png --spp 1 --resolution 4x4 --tone-map clip", &err), 0) << err;
  EXPECT_NE(run("s.json -o out2.png --spp 1 --resolution 4x4 --tone-map aces", &err), 0);
  EXPECT_FALSE(fs::exists(dir_ / "out2.png"));
}

TEST_F(SceneInput, MissingSceneFile) { expect_rejected("absent.json", {"absent.json", "not found"}); }

TEST_F(SceneInput, UnknownMaterialReference) {
  write("t.obj", kTriangleObj);
  write("s.json", scene_with(R"({"mesh": "t.obj", "material": "marble"})"));
  expect_rejected("s.json", {"s.json", "objects[0]", "unknown material 'marble'"});
}

TEST_F(SceneInput, UnknownMaterialType) {
  write("t.obj", kTriangleObj);
  write("s.json", scene_with(R"({"mesh": "t.obj", "material": "m"})", R"({"type":"velvet"})"));
  expect_rejected("s.json", {"s.json", "materials.m", "unknown material type 'velvet'"});
}

TEST_F(SceneInput, UnknownKey) {
  write("t.obj", kTriangleObj);
  write("s.json", scene_with(R"({"mesh": "t.obj", "material": "m", "colour": 1})"));
  expect_rejected("s.json", {"s.json", "unknown key 'colour'"});
}

TEST_F(SceneInput, OutOfRangeSkinParameter) {
  write("t.obj", kTriangleObj);
  write("s.json", scene_with(R"({"mesh": "t.obj", "material": "m"})", R"({"type":"skin","C_m":1.5})"));
  expect_rejected("s.json", {"s.json", "materials.m", "1.5"});
}

TEST_F(SceneInput, EmptyMesh) {
  write("e.obj", "# nothing here\n");
  write("s.json", scene_with(R"({"mesh": "e.obj", "material": "m"})"));
  expect_rejected("s.json", {"s.json", "e.obj", "no triangles"});
}

TEST_F(SceneInput, InvalidIndices) {
  write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
  write("s.json", scene_with(R"({"mesh": "bad.obj", "material": "m"})"));
  expect_rejected("s.json", {"s.json", "bad.obj", "vertex"});
}

TEST_F(SceneInput, InvalidGltf) {
  write("bad.glb", "glTF this is not a binary glTF");
  write("s.json", scene_with(R"({"mesh": "bad.glb", "material": "m"})"));
  expect_rejected("s.json", {"s.json", "bad.glb"});
}

TEST_F(SceneInput, BadOutputExtensionAndResolution) {
  std::string err;
  EXPECT_EQ(run("-o out.bmp --spp 1", &err), 2);
  EXPECT_NE(err.find("out.bmp"), std::string::npos) << err;
  EXPECT_EQ(run("-o out.png --resolution 0x5", &err), 2);
  EXPECT_NE(err.find("resolution"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir_ / "out.png"));
}

TEST_F(SceneInput, ExistingOutputSurvivesFailure) {
  write("out.png", "precious");
  write("s.json", "{");
  std::string err;
  EXPECT_EQ(run("s.json -o out.png", &err), 2);
  std::stringstream ss;
  ss << std::ifstream(dir_ / "out.png").rdbuf();
  EXPECT_EQ(ss.str(), "precious");
}

TEST_F(SceneInput, NonManifoldMeshRenders) {
  // Three triangles sharing one edge (non-manifold), a dangling vertex, a degenerate triangle
  // and a skin material: scanned meshes look like this and must render.
  write("nm.obj",
        "v 0 0 0\nv 0 1 0\nv 1 0 0\nv -1 0 0\nv 0 0 1\nv 5 5 5\n"
        "f 1 2 3\nf 1 2 4\nf 1 2 5\nf 1 1 2\n");
  write("s.json", scene_with(R"({"mesh": "nm.obj", "material": "m"})", R"({"type":"skin","preset":"african"})"));
  std::string err;
  EXPECT_EQ(run("s.json -o out.png --spp 2 --resolution 16x16", &err), 0) << err;
  EXPECT_TRUE(fs::exists(dir_ / "out.png"));
  const Image img = read_image((dir_ / "out.png").string());
  EXPECT_EQ(img.width, 16);
}

TEST_F(SceneInput, DefaultSceneWritesExr) {
  std::string err;
  EXPECT_EQ(run("-o out.exr --spp 1 --resolution 24x16", &err), 0) << err;
  const Image img = read_image((dir_ / "out.exr").string());
  EXPECT_EQ(img.width, 24);
  EXPECT_EQ(img.height, 16);
  // Linear floats: some pixel is lit, none is NaN.
  float mx = 0;
  for (float v : img.rgb) {
    EXPECT_TRUE(std::isfinite(v));
    EXPECT_GT(v, -0.02f);  // the blue profile dips below zero at a few mm (sRGB weights), so a
                           // single sample may be slightly negative; never by much
    mx = std::max(mx, v);
  }
  EXPECT_GT(mx, 0.01f);
}

// Layered materials choose their transport model like skin materials (the `solver` key; the
// registry's default without it); with g = 0.7 (outside the accurate tables) the accurate
// profile is radiative transfer in the spatial-frequency domain: no warning.
TEST_F(SceneInput, LayeredMaterialSolverAndValidity) {
  const std::string layered = R"({"type":"layered","layers":[{"sigma_a":0.2,"sigma_s_prime":2,"g":0.7}]})";
  write("t.obj", kTriangleObj);
  write("s.json", scene_with(R"({"mesh": "t.obj", "material": "m"})", layered));
  std::string err;
  ASSERT_EQ(run("s.json -o out.png --spp 1 --resolution 8x8", &err), 0) << err;
  EXPECT_EQ(err, "");
  // --solver multipole replaces it (no complaint: the layer is semi-infinite), and so does the key.
  ASSERT_EQ(run("s.json -o out.png --spp 1 --resolution 8x8 --solver multipole", &err), 0) << err;
  EXPECT_EQ(err, "");
  const std::string with_key = R"({"type":"layered","solver":"multipole","layers":[{"sigma_a":0.2,"sigma_s_prime":2,"g":0.7}]})";
  const Scene mp = Scene::parse(scene_with(R"({"sphere": {"center":[0,0,0], "radius":1}, "material": "m"})", with_key), "", "mp");
  EXPECT_TRUE(mp.validity().empty());
  const TranslucentMaterial& m = *mp.impl().data.materials.front().translucent();
  LayerStack stack;
  stack.layers = {Layer{0.2, 2.0, kInfinity, 1.4, 0.7}};
  EXPECT_EQ(m.R_d[0], DiffusionStack(stack).R_d());
  const Scene acc = Scene::parse(scene_with(R"({"sphere": {"center":[0,0,0], "radius":1}, "material": "m"})", layered), "", "acc");
  EXPECT_TRUE(acc.validity().empty());
  EXPECT_EQ(acc.impl().data.materials.front().translucent()->R_d[0], transport::find_model("accurate").R_d(stack));
}

TEST(Texture, RowZeroIsTheTopAndVIsUp) {
  // OpenGL convention (the Lee Perry-Smith GLB, PROVENANCE.md section 4): row = (1 - v) height.
  Texture t;
  t.width = 1;
  t.height = 2;
  t.rgb = {1, 0, 0, 0, 0, 1};  // row 0 (top) red, row 1 (bottom) blue
  EXPECT_EQ(t.lookup(0.5, 0.75).r, 1.0);
  EXPECT_EQ(t.lookup(0.5, 0.75).b, 0.0);
  EXPECT_EQ(t.lookup(0.5, 0.25).b, 1.0);
}

TEST(HeadMesh, LoadsWithNormalsAndUvs) {
  const std::string path = std::string(SKIN_SHARED_DATA_DIR) + "/meshes/LeePerrySmith/LeePerrySmith.glb";
  if (!fs::exists(path)) GTEST_SKIP() << "no head mesh at " << path;
  const auto meshes = load_mesh_file(path, 0);
  std::size_t tris = 0;
  for (const auto& m : meshes) {
    tris += m.triangles.size();
    EXPECT_EQ(m.normal.size(), m.position.size());
    EXPECT_EQ(m.uv.size(), m.position.size());
  }
  EXPECT_EQ(tris, 17684u);  // PROVENANCE.md section 4
}

TEST_F(SceneInput, LightNamingAnIlluminant) {
  // A light may name a CIE illuminant: D65 is the identity (the same image byte for byte), A
  // colours the light (another image), an unknown name is one line naming the light.
  write("t.obj", kTriangleObj);
  auto scene = [this](const std::string& light) {
    return R"({"camera": {"eye":[0.3,0.3,5], "look_at":[0.3,0.3,0], "fov": 10}, "materials": {"m": {"type":"diffuse"}},
      "objects": [{"mesh": "t.obj", "material": "m"}], "lights": [)" + light + "]}";
  };
  const char* args = " --spp 1 --resolution 8x8 --threads 1 --seed 3";
  std::string err;
  write("plain.json", scene(R"({"type": "directional", "direction": [0,0,-1], "irradiance": 2})"));
  write("d65.json", scene(R"({"type": "directional", "direction": [0,0,-1], "irradiance": 2, "illuminant": "D65"})"));
  write("a.json", scene(R"({"type": "directional", "direction": [0,0,-1], "irradiance": 2, "illuminant": "a"})"));
  ASSERT_EQ(run(std::string("plain.json -o plain.png") + args, &err), 0) << err;
  ASSERT_EQ(run(std::string("d65.json -o d65.png") + args, &err), 0) << err;
  ASSERT_EQ(run(std::string("a.json -o a.png") + args, &err), 0) << err;
  auto bytes = [this](const char* f) {
    std::stringstream ss;
    ss << std::ifstream(dir_ / f, std::ios::binary).rdbuf();
    return ss.str();
  };
  EXPECT_EQ(bytes("plain.png"), bytes("d65.png"));
  EXPECT_NE(bytes("plain.png"), bytes("a.png"));
  write("s.json", scene(R"({"type": "point", "position": [0,0,3], "intensity": 1, "illuminant": "D60"})"));
  expect_rejected("s.json", {"s.json", "lights[0]", "illuminant = 'D60' is unknown: must be one of D65"});
}

}  // namespace
}  // namespace skin::render
