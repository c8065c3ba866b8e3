// The schema of skin batch (batch_schema.hpp).
#include "batch_schema.hpp"

#include "skin/util/error.hpp"

namespace skin::schema {

using skin::util::format_number;

using skin::model::SkinSpectrum;

using skin::physics::ParameterInfo;
using skin::physics::SkinParameters;

std::vector<Column> batch_columns(const BatchLayout& layout, std::size_t first,
                                  std::span<const SkinParameters> sets,
                                  const std::vector<SkinSpectrum>& spectra,
                                  const std::vector<batch::RgbProfileResult>& profiles) {
  std::vector<Column> columns;
  Column index{"set", {}, {}};
  for (std::size_t i = 0; i < sets.size(); ++i) index.numbers.push_back(double(first + i));
  columns.push_back(index);
  for (const ParameterInfo* info : layout.keys) {
    Column col{std::string(info->key), {}, {}};
    for (const SkinParameters& p : sets) col.numbers.push_back(p.*(info->member));
    columns.push_back(col);
  }
  std::vector<Column> colour;
  for (const SkinSpectrum& s : spectra) append_rows(colour, color_columns(s.color));
  columns.insert(columns.end(), colour.begin(), colour.end());
  for (std::size_t w : layout.wavelengths) {
    Column col{"R_d_" + format_number(layout.grid[w]) + "nm", {}, {}};
    for (const SkinSpectrum& s : spectra) col.numbers.push_back(s.R_d[w]);
    columns.push_back(col);
  }
  const char* names[3] = {"r", "g", "b"};
  for (std::size_t k = 0; k < layout.radii.size(); ++k)
    for (std::size_t ch = 0; ch < 3; ++ch) {
      Column col{"R_" + format_number(layout.radii[k]) + "mm." + names[ch] + " [1/mm^2]", {}, {}};
      for (const batch::RgbProfileResult& p : profiles) col.numbers.push_back(p.profile.R[ch][layout.radius_index[k]]);
      columns.push_back(col);
    }
  return columns;
}

}  // namespace skin::schema
