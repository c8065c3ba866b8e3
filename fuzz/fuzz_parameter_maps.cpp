// Parameter maps (skin fit --texture writes them; a scene's "parameter_maps" reads them): the
// named float channels of an OpenEXR file (skin::image::read_exr_planes with the channels the fit
// writes). Invariant: every plane that reads has width x height values.
#include "fuzz_support.hpp"
#include "skin/image/image.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skin;
  static fuzz::InputFile input("exr");
  const std::string& path = input.write(data, size);
  image::Planes planes;
  if (!fuzz::accepts([&] {
        planes = image::read_exr_planes(path, {"melanin", "melanin_blend", "hemoglobin", "error"},
                                        "parameter maps");
      }))
    return 0;
  const std::size_t n = static_cast<std::size_t>(planes.width) * static_cast<std::size_t>(planes.height);
  if (planes.width <= 0 || planes.height <= 0 || planes.values.size() != 4)
    fuzz::finding("parameter maps read with an empty size or a missing plane");
  for (const auto& v : planes.values)
    if (v.size() != n) fuzz::finding("a plane's size does not match width x height");
  return 0;
}
