// Triangle meshes from Wavefront OBJ (tinyobjloader) and glTF 2.0 / GLB (tinygltf). Every
// index is checked: a bad file is reported by name, never crashes the renderer. Meshes need not
// be manifold (scanned heads rarely are).
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#endif
#include <tiny_gltf.h>
#include <tiny_obj_loader.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include <cstring>
#include <filesystem>
#include <map>
#include <tuple>

#include "scene_data.hpp"
#include "skin/util/atomic_file.hpp"
#include "skin/util/error.hpp"
#include "skin/util/input_file.hpp"

namespace skin::render {

using skin::util::InputError;

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw InputError("mesh = '" + path + "': " + what);
}

void check_mesh(const std::string& path, const Mesh& m) {
  if (m.triangles.empty()) fail(path, "no triangles");
  const auto n = m.position.size();
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (auto i : m.triangles[t])
      if (i >= n)
        fail(path, "triangle " + std::to_string(t) + " uses vertex " + std::to_string(i) +
                       ", but there are only " + std::to_string(n) + " vertices");
  for (const auto& p : m.position)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) fail(path, "vertex position is not finite");
  if (!m.normal.empty() && m.normal.size() != n) fail(path, "normal count differs from vertex count");
  if (!m.uv.empty() && m.uv.size() != n) fail(path, "texture coordinate count differs from vertex count");
}

std::vector<Mesh> load_obj(const std::string& path, std::size_t material) {
  tinyobj::ObjReaderConfig cfg;
  cfg.triangulate = true;
  cfg.vertex_color = false;
  cfg.mtl_search_path = std::filesystem::path(path).parent_path().string();
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, cfg)) {
    std::string err = reader.Error();
    while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
    fail(path, "cannot parse OBJ: " + (err.empty() ? std::string("unknown error") : err));
  }
  const auto& a = reader.GetAttrib();
  Mesh m;
  m.source = path;
  m.material = material;
  const bool has_n = !a.normals.empty(), has_uv = !a.texcoords.empty();
  std::map<std::tuple<int, int, int>, std::uint32_t> seen;
  const auto nv = static_cast<int>(a.vertices.size() / 3), nn = static_cast<int>(a.normals.size() / 3),
             nt = static_cast<int>(a.texcoords.size() / 2);
  bool all_n = has_n, all_uv = has_uv;
  for (const auto& shape : reader.GetShapes())
    for (const auto& idx : shape.mesh.indices) {
      all_n = all_n && idx.normal_index >= 0;
      all_uv = all_uv && idx.texcoord_index >= 0;
    }
  for (const auto& shape : reader.GetShapes()) {
    const auto& ix = shape.mesh.indices;
    for (std::size_t f = 0; f + 2 < ix.size(); f += 3) {
      std::array<std::uint32_t, 3> tri{};
      for (int k = 0; k < 3; ++k) {
        const auto& id = ix[f + static_cast<std::size_t>(k)];
        if (id.vertex_index < 0 || id.vertex_index >= nv)
          fail(path, "face uses vertex " + std::to_string(id.vertex_index + 1) + ", but there are only " + std::to_string(nv) + " vertices");
        if (all_n && id.normal_index >= nn) fail(path, "face uses a normal index out of range");
        if (all_uv && id.texcoord_index >= nt) fail(path, "face uses a texture coordinate index out of range");
        const auto key = std::make_tuple(id.vertex_index, all_n ? id.normal_index : -1, all_uv ? id.texcoord_index : -1);
        auto it = seen.find(key);
        if (it == seen.end()) {
          const auto vi = static_cast<std::size_t>(id.vertex_index) * 3;
          m.position.push_back({a.vertices[vi], a.vertices[vi + 1], a.vertices[vi + 2]});
          if (all_n) {
            const auto ni = static_cast<std::size_t>(id.normal_index) * 3;
            m.normal.push_back(normalize({a.normals[ni], a.normals[ni + 1], a.normals[ni + 2]}));
          }
          if (all_uv) {
            const auto ti = static_cast<std::size_t>(id.texcoord_index) * 2;
            m.uv.push_back({a.texcoords[ti], a.texcoords[ti + 1]});
          }
          it = seen.emplace(key, static_cast<std::uint32_t>(m.position.size() - 1)).first;
        }
        tri[static_cast<std::size_t>(k)] = it->second;
      }
      m.triangles.push_back(tri);
    }
  }
  check_mesh(path, m);
  return {std::move(m)};
}

// Column-major 4x4 transform of glTF nodes.
using Mat4 = std::array<double, 16>;
Mat4 identity() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }
Mat4 mul(const Mat4& a, const Mat4& b) {
  Mat4 r{};
  for (int c = 0; c < 4; ++c)
    for (int rr = 0; rr < 4; ++rr) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a[static_cast<std::size_t>(k * 4 + rr)] * b[static_cast<std::size_t>(c * 4 + k)];
      r[static_cast<std::size_t>(c * 4 + rr)] = s;
    }
  return r;
}
Mat4 node_matrix(const tinygltf::Node& n) {
  if (n.matrix.size() == 16) {
    Mat4 m{};
    for (std::size_t i = 0; i < 16; ++i) m[i] = n.matrix[i];
    return m;
  }
  Mat4 t = identity(), r = identity(), s = identity();
  if (n.translation.size() == 3) { t[12] = n.translation[0]; t[13] = n.translation[1]; t[14] = n.translation[2]; }
  if (n.rotation.size() == 4) {
    const double x = n.rotation[0], y = n.rotation[1], z = n.rotation[2], w = n.rotation[3];
    r = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w), 0,
         2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w), 0,
         2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y), 0,
         0, 0, 0, 1};
  }
  if (n.scale.size() == 3) { s[0] = n.scale[0]; s[5] = n.scale[1]; s[10] = n.scale[2]; }
  return mul(t, mul(r, s));
}
Vec3 xform_point(const Mat4& m, const Vec3& p) {
  return {m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12], m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13],
          m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14]};
}
Vec3 xform_normal(const Mat4& m, const Vec3& n) {
  // Inverse transpose of the upper 3x3 via cofactors (the determinant's scale cancels on
  // normalisation; its sign is fixed by the integrator, which orients normals per hit).
  const double a = m[0], b = m[4], c = m[8], d = m[1], e = m[5], f = m[9], g = m[2], h = m[6], i = m[10];
  const Vec3 r0{e * i - f * h, -(d * i - f * g), d * h - e * g};
  const Vec3 r1{-(b * i - c * h), a * i - c * g, -(a * h - b * g)};
  const Vec3 r2{b * f - c * e, -(a * f - c * d), a * e - b * d};
  return normalize(r0 * n.x + r1 * n.y + r2 * n.z);
}

// Reads `count` x `comps` floats of an accessor (float components only, any byte stride).
std::vector<double> read_floats(const std::string& path, const tinygltf::Model& model, int accessor, int comps) {
  if (accessor < 0 || accessor >= static_cast<int>(model.accessors.size())) fail(path, "accessor index out of range");
  const auto& acc = model.accessors[static_cast<std::size_t>(accessor)];
  if (acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT) fail(path, "only float vertex attributes are supported");
  if (tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type)) != comps) fail(path, "vertex attribute has the wrong number of components");
  if (acc.bufferView < 0 || acc.bufferView >= static_cast<int>(model.bufferViews.size())) fail(path, "buffer view index out of range");
  const auto& view = model.bufferViews[static_cast<std::size_t>(acc.bufferView)];
  if (view.buffer < 0 || view.buffer >= static_cast<int>(model.buffers.size())) fail(path, "buffer index out of range");
  const auto& buf = model.buffers[static_cast<std::size_t>(view.buffer)].data;
  const std::size_t stride = view.byteStride ? view.byteStride : sizeof(float) * static_cast<std::size_t>(comps);
  const std::size_t start = view.byteOffset + acc.byteOffset;
  if (acc.count > 0 && start + (acc.count - 1) * stride + sizeof(float) * static_cast<std::size_t>(comps) > buf.size())
    fail(path, "vertex data runs past the end of its buffer");
  std::vector<double> out(acc.count * static_cast<std::size_t>(comps));
  for (std::size_t i = 0; i < acc.count; ++i)
    for (int k = 0; k < comps; ++k) {
      float v;
      std::memcpy(&v, buf.data() + start + i * stride + sizeof(float) * static_cast<std::size_t>(k), sizeof v);
      out[i * static_cast<std::size_t>(comps) + static_cast<std::size_t>(k)] = v;
    }
  return out;
}

std::vector<std::uint32_t> read_indices(const std::string& path, const tinygltf::Model& model, int accessor) {
  if (accessor < 0 || accessor >= static_cast<int>(model.accessors.size())) fail(path, "index accessor out of range");
  const auto& acc = model.accessors[static_cast<std::size_t>(accessor)];
  std::size_t size = 0;
  switch (acc.componentType) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: size = 1; break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: size = 2; break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: size = 4; break;
    default: fail(path, "indices must be unsigned integers");
  }
  if (acc.bufferView < 0 || acc.bufferView >= static_cast<int>(model.bufferViews.size())) fail(path, "buffer view index out of range");
  const auto& view = model.bufferViews[static_cast<std::size_t>(acc.bufferView)];
  if (view.buffer < 0 || view.buffer >= static_cast<int>(model.buffers.size())) fail(path, "buffer index out of range");
  const auto& buf = model.buffers[static_cast<std::size_t>(view.buffer)].data;
  const std::size_t stride = view.byteStride ? view.byteStride : size;
  const std::size_t start = view.byteOffset + acc.byteOffset;
  if (acc.count > 0 && start + (acc.count - 1) * stride + size > buf.size()) fail(path, "index data runs past the end of its buffer");
  std::vector<std::uint32_t> out(acc.count);
  for (std::size_t i = 0; i < acc.count; ++i) {
    const unsigned char* p = buf.data() + start + i * stride;
    if (size == 1) out[i] = p[0];
    else if (size == 2) { std::uint16_t v; std::memcpy(&v, p, 2); out[i] = v; }
    else std::memcpy(&out[i], p, 4);
  }
  return out;
}

void add_gltf_mesh(const std::string& path, const tinygltf::Model& model, int mesh_index, const Mat4& xf,
                   std::size_t material, std::vector<Mesh>& out) {
  if (mesh_index < 0 || mesh_index >= static_cast<int>(model.meshes.size())) fail(path, "node refers to a missing mesh");
  for (const auto& prim : model.meshes[static_cast<std::size_t>(mesh_index)].primitives) {
    if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES) continue;  // points, lines: skipped
    const auto pos_it = prim.attributes.find("POSITION");
    if (pos_it == prim.attributes.end()) fail(path, "primitive without POSITION");
    Mesh m;
    m.source = path;
    m.material = material;
    const auto pos = read_floats(path, model, pos_it->second, 3);
    for (std::size_t i = 0; i + 2 < pos.size(); i += 3) m.position.push_back(xform_point(xf, {pos[i], pos[i + 1], pos[i + 2]}));
    if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
      const auto n = read_floats(path, model, it->second, 3);
      for (std::size_t i = 0; i + 2 < n.size(); i += 3) m.normal.push_back(xform_normal(xf, {n[i], n[i + 1], n[i + 2]}));
    }
    if (auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end()) {
      const auto t = read_floats(path, model, it->second, 2);
      for (std::size_t i = 0; i + 1 < t.size(); i += 2) m.uv.push_back({t[i], t[i + 1]});
    }
    std::vector<std::uint32_t> idx;
    if (prim.indices >= 0) idx = read_indices(path, model, prim.indices);
    else for (std::uint32_t i = 0; i < m.position.size(); ++i) idx.push_back(i);
    if (idx.size() % 3 != 0) fail(path, "index count is not a multiple of 3");
    for (std::size_t i = 0; i < idx.size(); i += 3) m.triangles.push_back({idx[i], idx[i + 1], idx[i + 2]});
    check_mesh(path, m);
    out.push_back(std::move(m));
  }
}

void visit(const std::string& path, const tinygltf::Model& model, int node, const Mat4& parent,
           std::size_t material, std::vector<Mesh>& out, int depth) {
  if (node < 0 || node >= static_cast<int>(model.nodes.size()) || depth > 64) fail(path, "bad node hierarchy");
  const auto& n = model.nodes[static_cast<std::size_t>(node)];
  const Mat4 xf = mul(parent, node_matrix(n));
  if (n.mesh >= 0) add_gltf_mesh(path, model, n.mesh, xf, material, out);
  for (int c : n.children) visit(path, model, c, xf, material, out, depth + 1);
}

bool skip_images(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                 const unsigned char*, int, void*) {
  return true;  // textures come from the scene file, not from the glTF material
}

std::vector<Mesh> load_gltf(const std::string& path, std::size_t material) {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(skip_images, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = util::io::extension(path) == "glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                                               : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  if (!ok) {
    while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
    fail(path, "cannot parse glTF: " + (err.empty() ? std::string("unknown error") : err));
  }
  std::vector<Mesh> out;
  const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
  if (scene < static_cast<int>(model.scenes.size())) {
    for (int n : model.scenes[static_cast<std::size_t>(scene)].nodes) visit(path, model, n, identity(), material, out, 0);
  } else {
    for (int i = 0; i < static_cast<int>(model.meshes.size()); ++i) add_gltf_mesh(path, model, i, identity(), material, out);
  }
  if (out.empty()) fail(path, "no triangles");
  return out;
}

}  // namespace

std::vector<Mesh> load_mesh_file(const std::string& path, std::size_t material) {
  util::io::check_input_file(path, "mesh");
  const std::string ext = util::io::extension(path);
  if (ext == "obj") return load_obj(path, material);
  if (ext == "gltf" || ext == "glb") return load_gltf(path, material);
  fail(path, "unknown mesh format '." + ext + "': use .obj, .gltf or .glb");
}

}  // namespace skin::render
