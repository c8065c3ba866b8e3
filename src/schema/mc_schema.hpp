#pragma once
// The schema of `skin mc`'s output (schema.hpp).
#include <cstdint>
#include <optional>
#include <string>

#include "schema.hpp"
#include "skin/mc/mc.hpp"

namespace skin::schema {

// The skin a Monte Carlo stack was made of (skin mc --wavelength).
struct McSkin {
  std::string preset;
  physics::SkinParameters parameters;
  double wavelength_nm = 0;
};

// Monte Carlo in `stack` (its layers with sigma_s too): the totals per power that entered with
// their standard errors, per incident power, the lost weight, the photons, `seed`, the wall time
// and the profile R(r) with its standard error; with `skin`, what the stack was made of.
Result mc_result(const physics::LayerStack& stack, const mc::Result& r, std::uint64_t seed,
                 const std::optional<McSkin>& skin = std::nullopt);

}  // namespace skin::schema
