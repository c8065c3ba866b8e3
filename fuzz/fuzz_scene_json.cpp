// Scene files (skin render SCENE.json): skin::render::Scene::parse on the fuzzer's JSON, with
// relative paths resolved in fuzz/assets (a triangle OBJ and glTF, small PNG and EXR textures,
// parameter maps), so that a scene may reference meshes and textures. The Embree scene and the
// materials' profiles are built as for a render; nothing is rendered.
#include "fuzz_support.hpp"
#include "skin/render/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skin;
  fuzz::accepts([&] {
    const render::Scene scene = render::Scene::parse(std::string(fuzz::text(data, size)), SKIN_FUZZ_ASSETS, "fuzz.json");
    if (scene.width() <= 0 || scene.height() <= 0) fuzz::finding("a parsed scene has no resolution");
  });
  return 0;
}
