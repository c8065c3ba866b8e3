// Calls into every library of the installed package, so that the link pulls each one's objects
// and with them its private dependencies (tests/install). Prints "ok" and the parts used.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "skin/color/illuminant.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/transport/model.hpp"
#include "skin/util/error.hpp"
#include "skin/util/table.hpp"
#ifdef SKIN_HAVE_MC
#include "skin/mc/mc.hpp"
#endif
#ifdef SKIN_HAVE_IMAGE
#include "skin/image/image.hpp"
#endif
#ifdef SKIN_HAVE_FIT
#include "skin/fit/color_fit.hpp"
#endif
#ifdef SKIN_HAVE_RENDER
#include "skin/render/scene.hpp"
#endif
#ifdef SKIN_HAVE_BATCH
#include "skin/batch/batch.hpp"
#endif
#ifdef SKIN_HAVE_EXPORT
#include "skin/export/export.hpp"
#endif

int main() {
  std::string parts = "util physics transport color model";
  const skin::util::Table t = skin::util::parse_csv("a,b\n1,2\n", "t.csv");
  const skin::physics::WavelengthGrid grid(550, 550, 1);
  const skin::model::SkinSpectrum s = skin::model::skin_spectrum(skin::physics::find_preset("caucasian").parameters, grid,
                                                   skin::transport::default_model());
  if (t.rows() != 1 || !(s.R_d[0] > 0) || skin::color::find_illuminant("d65").name() != "D65") return 1;
#ifdef SKIN_HAVE_MC
  if (!(skin::mc::memory_bytes(skin::mc::Options{}) > 0)) return 1;
  parts += " mc";
#endif
#ifdef SKIN_HAVE_IMAGE
  {
    const auto path = std::filesystem::temp_directory_path() / "skin_all_targets.png";
    skin::image::Image img(2, 2);
    img.set(1, 1, {1.0, 0.5, 0.25});
    skin::image::write_image(path.string(), img);
    const skin::image::Image back = skin::image::read_image(path.string());
    std::filesystem::remove(path);
    if (back.width != 2 || !(back.at(1, 1).r > 0.9)) return 1;
    parts += " image";
  }
#endif
#ifdef SKIN_HAVE_FIT
  if (!(skin::fit::parse_hex("#c08a70").r > 0)) return 1;
  parts += " fit";
#endif
#ifdef SKIN_HAVE_RENDER
  try {
    skin::render::Scene::parse("not json", ".", "scene.json");
    return 1;
  } catch (const skin::util::InputError&) {
    parts += " render";
  }
#endif
#ifdef SKIN_HAVE_BATCH
  if (skin::batch::spectra(std::vector<skin::physics::SkinParameters>(2), grid, skin::transport::default_model()).size() != 2)
    return 1;
  parts += " batch";
#endif
#ifdef SKIN_HAVE_EXPORT
  if (skin::exporting::target_names_text().empty()) return 1;
  parts += " export";
#endif
  std::printf("ok %s\n", parts.c_str());
  return 0;
}
