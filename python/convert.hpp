#pragma once
// The Python module's conversions that need no Python: the checks of what a call passed, once
// the values are plain C++ (fuzz/fuzz_python_convert.cpp feeds them arbitrary input).
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "skin/physics/layer.hpp"

namespace skin::python {

inline constexpr std::string_view kLayerKeys = "keys: sigma_a, sigma_s_prime, thickness_mm (or thickness), eta, g";

// Layer `index` (0-based) of layers(), mc(layers=...) from its dict's keys and values (nullopt:
// None), as `skin layers --layer` reads one: sigma_a and sigma_s_prime are required, None is
// allowed for the thickness only (semi-infinite), an unknown key is refused. InputError names the
// layer ("layer 1: sigma_s_prime is missing: ...").
physics::Layer layer_from_entries(const std::vector<std::pair<std::string, std::optional<double>>>& entries,
                         std::size_t index);

// A texture's linear sRGB values (fit_texture), rows of `width` pixels of 3: each must be in
// [0, 1], what an 8- or 16-bit texture holds; InputError names the first other one
// ("image[y, x, c] = nan is out of range: ...").
void check_linear_rgb(const std::vector<float>& rgb, std::size_t width);

}  // namespace skin::python
