#pragma once
// The schema of `skin batch`'s output (schema.hpp): CSV columns, one row per parameter set.
#include <cstddef>
#include <span>
#include <vector>

#include "schema.hpp"
#include "skin/batch/batch.hpp"

namespace skin::schema {

// What each row holds beyond the set's number and its colour.
struct BatchLayout {
  std::vector<const physics::ParameterInfo*> keys;  // the parameters the sets give (one column each)
  physics::WavelengthGrid grid;
  std::vector<std::size_t> wavelengths;    // grid indices: columns R_d_<nm>nm
  std::vector<double> radii;               // --radius [mm] as asked: columns R_<mm>mm.r/g/b
  std::vector<std::size_t> radius_index;   // each one's index in the profiles' radial grid
};

// The rows of the sets numbered first, first + 1, ...: columns set, the keys, the colour (as
// color_columns), R_d at the wavelengths, the RGB profile at the radii (`profiles`: one per set,
// or none when there are no radii).
std::vector<Column> batch_columns(const BatchLayout& layout, std::size_t first,
                                  std::span<const physics::SkinParameters> sets,
                                  const std::vector<model::SkinSpectrum>& spectra,
                                  const std::vector<batch::RgbProfileResult>& profiles);

}  // namespace skin::schema
