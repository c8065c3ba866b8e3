// Meshes of scenes (the "mesh" of an object, skin figure --mesh): the renderer's loader
// (skin::render::load_mesh_file: tinyobjloader, tinygltf) on a file of the extension this target
// is built for (SKIN_FUZZ_EXTENSION: obj, gltf or glb). Invariant: a mesh that loads has
// indices within its vertices and finite positions (what the renderer then relies on).
#include <cmath>

#include "fuzz_support.hpp"
#include "scene_data.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skin;
  static fuzz::InputFile input(SKIN_FUZZ_EXTENSION);
  const std::string& path = input.write(data, size);
  std::vector<render::Mesh> meshes;
  if (!fuzz::accepts([&] { meshes = render::load_mesh_file(path, 0); })) return 0;
  for (const auto& m : meshes) {
    for (const auto& tri : m.triangles)
      for (const auto i : tri)
        if (i >= m.position.size()) fuzz::finding("a loaded mesh has an index beyond its vertices");
    if ((!m.normal.empty() && m.normal.size() != m.position.size()) ||
        (!m.uv.empty() && m.uv.size() != m.position.size()))
      fuzz::finding("a loaded mesh has normals or uvs not one per vertex");
    for (const auto& p : m.position)
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        fuzz::finding("a loaded mesh has a vertex that is not finite");
  }
  return 0;
}
