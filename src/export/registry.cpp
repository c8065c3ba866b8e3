// The registry of export targets (target.hpp): every target, once, in the order of targets()
// (the help texts, --target all, messages). Each target is defined in its family's file by a
// function NAME_target() returning its TargetSpec (its name, description, extension, usual unit,
// writer and, if it takes textures, its texel fit). A new target is that function in its file
// and one line in SKIN_EXPORT_TARGETS (src/export/*.cpp are compiled by a glob).
#include <string>

#include "target.hpp"
#include "skin/util/error.hpp"

#define SKIN_EXPORT_TARGETS(X) \
  X(openpbr)                   \
  X(standard_surface)          \
  X(cycles)                    \
  X(unreal)                    \
  X(unity)                     \
  X(pbrt_v4)                   \
  X(mitsuba3)                  \
  X(realtime)                  \
  X(profile)                   \
  X(gltf)

namespace skin::exporting {

using skin::util::InputError;

namespace detail {

#define SKIN_EXPORT_DECLARE(t) TargetSpec t##_target();
SKIN_EXPORT_TARGETS(SKIN_EXPORT_DECLARE)
#undef SKIN_EXPORT_DECLARE

const std::vector<TargetSpec>& registry() {
#define SKIN_EXPORT_ENTRY(t) t##_target(),
  static const std::vector<TargetSpec> specs = {SKIN_EXPORT_TARGETS(SKIN_EXPORT_ENTRY)};
#undef SKIN_EXPORT_ENTRY
  return specs;
}

const TargetSpec& find_spec(std::string_view name) {
  for (const TargetSpec& s : registry())
    if (s.name == name) return s;
  throw InputError("target = '" + std::string(name) + "' is unknown: must be one of " +
                   target_names_text());
}

}  // namespace detail

const std::vector<Target>& targets() {
  static const std::vector<Target> list = [] {
    std::vector<Target> t;
    for (const detail::TargetSpec& s : detail::registry())
      t.push_back({s.name, s.description, s.extension, s.default_unit, s.texel != nullptr});
    return t;
  }();
  return list;
}

const Target& find_target(std::string_view name) {
  const std::vector<Target>& all = targets();
  return all[&detail::find_spec(name) - detail::registry().data()];
}

std::string target_names_text() {
  std::string s;
  for (const Target& t : targets()) s += (s.empty() ? "" : ", ") + std::string(t.name);
  return s;
}

std::string default_stem(const Target& target, std::string_view name) {
  return std::string(name) + "." + std::string(target.name);
}

void require_textures(const Target& target) {
  if (target.takes_textures) return;
  std::string which;
  for (const Target& t : targets())
    if (t.takes_textures) which += (which.empty() ? "" : ", ") + std::string(t.name);
  throw InputError("parameter-maps: target " + std::string(target.name) +
                   " takes no textures (its profile is one per material); targets that do: " +
                   which);
}

}  // namespace skin::exporting
