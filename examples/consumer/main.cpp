// Uses the installed library: the colour of the caucasian preset (as `skin color --preset
// caucasian` prints it) and R_d at 550 nm for a melanin sweep, computed on all cores.
#include <cstdio>
#include <vector>

#include "skin/batch/batch.hpp"
#include "skin/model/skin_model.hpp"

int main() {
  const skin::model::SkinSpectrum s = skin::model::skin_spectrum(skin::physics::find_preset("caucasian").parameters);
  std::printf("caucasian %s\n", s.color.hex.c_str());
  std::vector<skin::physics::SkinParameters> sweep(5);
  for (std::size_t i = 0; i < sweep.size(); ++i) sweep[i].melanin = 0.1 * static_cast<double>(i);
  const skin::physics::WavelengthGrid grid(550, 550, 1);
  for (const auto& x : skin::batch::spectra(sweep, grid, skin::transport::default_model()))
    std::printf("melanin %.1f R_d(550 nm) %.6f\n", x.parameters.melanin, x.R_d[0]);
  return 0;
}
