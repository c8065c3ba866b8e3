#pragma once
// A scene's data, internal (not installed: the public face is skin/render/scene.hpp): as
// described (SceneDescription::Data, MaterialDescription: no physics) and as built (SceneData,
// Material: profiles computed; docs/renderer.md, "Describe, then build"). Geometry is in scene units; `mm_per_unit` converts to the mm of the diffusion profiles.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <variant>
#include <string>
#include <vector>

#include "skin/model/skin_model.hpp"
#include "skin/transport/model.hpp"
#include "skin/physics/skin_parameters.hpp"
#include "skin/image/image.hpp"
#include "lights.hpp"
#include "skin/render/math.hpp"
#include "skin/render/microfacet.hpp"
#include "skin/render/profile_sampler.hpp"
#include "skin/render/sampling.hpp"
#include "skin/render/scene.hpp"
#include "spectral.hpp"

namespace skin::render {

// An RGB image in linear values, row 0 at the top.
struct Texture {
  std::string path;
  int width = 0, height = 0;
  std::vector<float> rgb;  // width * height * 3, linear
  // Bilinear lookup with wrapping, (u, v) in the OpenGL/glTF-as-exported convention used by the
  // loader: v = 0 at the bottom row, so row = (1 - v) * height (PROVENANCE.md section 4).
  Rgb3 lookup(double u, double v) const;
  Rgb3 texel(int x, int y) const;
};

enum class MaterialKind { diffuse, skin, layered };

// A parameter map of a skin material: sets one parameter from one channel of a texture
// (load_map_texture): either the parameter's value itself (`values`; the nodes span the
// texture's range) or, with min and max given, value = min + texel x (max - min). The BSSRDF is
// precomputed at the nodes of a regular grid over the mapped parameters (first map fastest), and
// a shading point uses one node chosen at random with its multilinear interpolation weight: in
// expectation, the profiles interpolated multilinearly in parameter space.
struct ParameterMap {
  double physics::SkinParameters::*member = nullptr;
  std::string key;  // parameter key (skin::physics::parameter_table())
  std::shared_ptr<const Texture> texture;
  double min = 0, max = 1;  // the nodes' range
  bool values = false;      // texels are values (else fractions of [min, max])
  int levels = 2;
};

// A material as the scene file (or the CLI's flags, or `skin figure`) describes it: no physics
// yet. build_scene turns it into a Material.
struct MaterialDescription {
  std::string name;
  MaterialKind kind = MaterialKind::diffuse;
  Rgb3 albedo{0.5, 0.5, 0.5};                 // diffuse: reflectance
  std::shared_ptr<const Texture> albedo_map;  // diffuse: reflectance; translucent: colour to reproduce
  physics::SkinParameters parameters;                  // skin
  const transport::Model* solver = &transport::default_model();  // translucent (the key `solver`)
  std::array<physics::LayerStack, 3> stacks;           // layered: the stack per channel
  double rho_s = 0, roughness = 0.35, eta = 1.4;  // layered (skin: from its parameters)
  // Skin with an albedo texture: the chromophores assumed to have produced it (DJ06 section
  // 3.6; default: the material's own parameters).
  std::optional<physics::SkinParameters> texture_reference;
  std::vector<ParameterMap> maps;             // skin
  bool as_diffuse = false;  // translucent: rendered as a diffuse material of its R_d (--diffuse)
  bool translucent() const { return kind != MaterialKind::diffuse; }
};

// The spectral profiles of one skin (spectral rendering): a table per wavelength of a 10 nm grid
// over 400-700 nm, rescaled to each wavelength's exact R_d.
struct SpectralSkin {
  physics::WavelengthGrid grid{kLambdaMin, kLambdaMax, 10.0};
  std::vector<TabulatedProfile> profile;  // per grid wavelength
  // The four channels at the sample's wavelengths: the two nearest tables mixed linearly.
  std::array<ProfileChannel, kWavelengths> channels(const SampledWavelengths& wl) const;
};
// A function of wavelength on the spectral grid, linear between its nodes.
struct SpectralCurve {
  physics::WavelengthGrid grid{kLambdaMin, kLambdaMax, 10.0};
  std::vector<double> values;
  double operator()(double lambda) const;
};

// A material ready to render (built from its MaterialDescription): one of a closed set of
// types, each with its own terms (the integrator visits the type; integrator.cpp).
// Diffuse: a Lambertian surface term only.
struct DiffuseMaterial {
  Rgb3 albedo{0.5, 0.5, 0.5};                 // reflectance
  std::shared_ptr<const Texture> albedo_map;  // reflectance
};
// Translucent (skin or layered): a surface term, the Torrance-Sparrow lobe scaled by rho_s, and
// a subsurface term, the BSSRDF of its diffusion profiles.
struct TranslucentMaterial {
  const transport::Model* solver = &transport::default_model();  // of the profiles
  transport::Validity validity;               // of the profiles (skin: over wavelength)
  std::array<TabulatedProfile, 3> profile;    // R(r) per linear sRGB channel [1/mm^2]
  Rgb3 R_d;                                   // totals per channel
  std::shared_ptr<const Texture> albedo_map;  // colour to reproduce
  Rgb3 texture_normalisation{1, 1, 1};        // 1 / R_d colour of the texture's reference
  // Spectral rendering (skin only): per-wavelength profiles, and the R_d spectrum of the
  // texture's reference (DJ06 section 3.6, per wavelength).
  std::shared_ptr<const SpectralSkin> spectral;
  std::shared_ptr<const SpectralCurve> spectral_texture_reference;
  double rho_s = 0, roughness = 0.35, eta = 1.4;
  std::shared_ptr<const SpecularAlbedo> specular_albedo;
  // Parameter maps (skin only): the maps and the materials at their grid's nodes.
  std::vector<ParameterMap> maps;
  std::vector<TranslucentMaterial> nodes;
  bool has_maps() const { return !maps.empty(); }
  // The node for texture coordinates (u, v) and a uniform random number.
  const TranslucentMaterial& node_at(double u, double v, double xi) const;
};
struct Material {
  std::string name;
  std::variant<DiffuseMaterial, TranslucentMaterial> type;
  const TranslucentMaterial* translucent() const { return std::get_if<TranslucentMaterial>(&type); }
};

struct Mesh {
  std::string source;  // file it came from (or "built-in ...") for messages
  std::vector<Vec3> position, normal;  // normal empty: flat shading from the triangle
  std::vector<Vec2> uv;                // empty: no texture coordinates
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::size_t material = 0;
};

struct Camera {
  Vec3 eye{0, 0, 5}, target{0, 0, 0}, up{0, 1, 0};
  double fov_deg = 40;  // vertical field of view
  int width = 384, height = 256;
};

// What a scene holds besides its materials (the same in its description and once built).
struct SceneSetup {
  std::string source;  // scene file or "built-in default scene"
  Camera camera;
  double mm_per_unit = 1.0;
  std::vector<Mesh> meshes;
  std::vector<Light> lights;
  Environment environment;
  int spp = 16, max_depth = 5;
  // The subsurface term (RenderSettings::subsurface): probes, or the point cloud with its spacing
  // [mm] and tree threshold [sr] (the scene's `render` keys subsurface, point_spacing,
  // point_solid_angle).
  bool subsurface_points = false;
  double point_spacing = 0.5, point_solid_angle = 0.05;
  double exposure = 0.0;  // stops, applied to PNG output
  bool spectral = false;  // spectral rendering (the scene key render.spectral, --spectral)
  image::ToneMap tone_map = image::ToneMap::clip;  // PNG output
};

// A scene described (parsed, built in, edited): SceneDescription's data.
struct SceneDescription::Data : SceneSetup {
  std::vector<MaterialDescription> materials;
};

// A scene built: every material's profiles computed.
struct SceneData : SceneSetup {
  std::vector<Material> materials;
};

// The radii of the renderer's profile tables [mm].
transport::RadialGrid skin_profile_radii();
// The build: each distinct (parameters, solver, spectral) of skin (materials and parameter-map
// nodes over all the descriptions) and each distinct layered material computed once, in
// parallel; InputError names the scene and material.
// With a progress callback, the jobs that solve profiles run one after the other and report
// progress(done, total) per wavelength (channel, for layered materials) of those jobs.
std::vector<SceneData> build_scenes(const std::vector<const SceneDescription::Data*>& descriptions,
                                    const util::ProgressCallback& progress = {});
BuildWork build_work(const std::vector<const SceneDescription::Data*>& descriptions);
// Spectral rendering needs a spectrum of every material: InputError for a layered one.
void check_spectral(const SceneDescription::Data& s);
// One translucent material alone (tests, benchmarks): a skin or layered description built as
// build_scenes builds it.
TranslucentMaterial build_translucent(const MaterialDescription& d, bool spectral = false);
MaterialDescription skin_description(const physics::SkinParameters& p,
                                     const transport::Model& solver = transport::default_model());
MaterialDescription layered_description(const std::array<physics::LayerStack, 3>& stacks,
                                        const transport::Model& solver = transport::default_model());

// Procedural geometry for built-in scenes (in scene units).
Mesh make_sphere(const Vec3& centre, double radius, int n_theta, int n_phi, std::size_t material);
Mesh make_ellipsoid(const Vec3& centre, const Vec3& radii, int n_theta, int n_phi,
                    std::size_t material);
Mesh make_quad(const Vec3& corner, const Vec3& edge_u, const Vec3& edge_v, std::size_t material);

// Loading (throw InputError naming the file and the problem).
std::vector<Mesh> load_mesh_file(const std::string& path, std::size_t material);
std::shared_ptr<Texture> load_texture(const std::string& path, bool srgb);
// A parameter map's texture: one channel of data (no transfer curve) in the red component.
// OpenEXR: the channel named `channel`, or the parameter's `key` when `channel` is empty (as
// `skin fit --texture` writes them); a missing channel is an error. Other formats: the red
// channel ('channel' "R", "G" or "B" picks another).
std::shared_ptr<Texture> load_map_texture(const std::string& path, const std::string& channel,
                                          const std::string& key);

}  // namespace skin::render
