#pragma once
// A target as the registry holds it (TargetSpec) and what its writer is given (Context); internal
// to skin::export. Each target is defined in its family's file (materialx.cpp, cycles.cpp,
// engines.cpp, pbrt.cpp, mitsuba.cpp, realtime.cpp, profile.cpp, gltf.cpp) and listed once in the registry
// (registry.cpp); the fits the families share are in fits.hpp, the report and the number
// formatting in report.hpp, the parameter maps in maps.cpp. docs/export.md gives every mapping
// and its source.
#include <cstddef>
#include <string_view>
#include <vector>

#include "reference.hpp"
#include "skin/export/export.hpp"
#include "skin/util/progress.hpp"

namespace skin::exporting::detail {

// One texel of parameter maps through a target that takes textures.
struct TexelFit {
  util::Rgb color;      // the target's colour parameter (linear)
  util::Rgb radius_mm;  // its radius parameter, mm (before the unit)
  double delta_e = 0;
};

// Parameter maps through a target: per texel, the target's colour and radius.
struct MapsFit {
  int width = 0, height = 0;
  std::vector<TexelFit> texels;  // width * height
  std::size_t distinct = 0;
  double max_delta_e = 0;
};

// What a writer is given.
struct Context {
  const Target& target;
  const Reference& ref;    // our skin
  const Options& options;  // validated, stem set
  Unit unit;               // of the files: options.unit, or the target's usual one
  const MapsFit* maps;     // the per-texel fits with --parameter-maps, else null
  // Length in the files per mm (the unit times the world scale).
  double scale() const { return per_mm(unit) * options.world_scale; }
};

// A target: its line in targets() and its writer. `texel` (targets that take textures, i.e.
// --parameter-maps) fits one texel; fit_maps runs it over the maps and the writer gets the result
// in Context::maps.
struct TargetSpec {
  std::string_view name;         // --target
  std::string_view description;  // one line
  std::string_view extension;    // of the main file, with the dot
  Unit default_unit;             // the target's usual scene unit
  Export (*write)(const Context&) = nullptr;
  TexelFit (*texel)(const Reference&) = nullptr;
};

// The registered targets, in the order of targets() (registry.cpp).
const std::vector<TargetSpec>& registry();
const TargetSpec& find_spec(std::string_view name);

// Fits every distinct texel of `maps` (parameters over `base`) through `texel`, in parallel.
MapsFit fit_maps(TexelFit (*texel)(const Reference&), const physics::SkinParameters& base,
                 const transport::Model& model, const ParameterMapsInput& maps,
                 const util::ProgressCallback& progress);
// The two textures of a maps fit: colour (PNG, sRGB-encoded) and radius (EXR, linear, in the
// file's unit: radius_mm x radius_scale).
void add_textures(Export& e, const MapsFit& mf, double radius_scale);

}  // namespace skin::exporting::detail
