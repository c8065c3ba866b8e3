// Textures (a scene's albedo_texture and environment map, skin fit --texture): the renderer's
// loader (skin::render::load_texture over skin::image::read_image: stb_image, OpenEXR) on a file
// of the extension this target is built for (SKIN_FUZZ_EXTENSION: png, jpg or exr), and the
// same file as a parameter map's texture (load_map_texture, red channel or EXR channel
// "melanin"). Invariant: a texture that loads has width x height texels.
#include "fuzz_support.hpp"
#include "scene_data.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skin;
  static fuzz::InputFile input(SKIN_FUZZ_EXTENSION);
  const std::string& path = input.write(data, size);
  std::shared_ptr<render::Texture> t;
  auto check = [&] {
    if (t->width <= 0 || t->height <= 0 ||
        t->rgb.size() != static_cast<std::size_t>(t->width) * static_cast<std::size_t>(t->height) * 3)
      fuzz::finding("a loaded texture's size does not match its texels");
  };
  if (fuzz::accepts([&] { t = render::load_texture(path, true); })) check();
  if (fuzz::accepts([&] { t = render::load_map_texture(path, "", "melanin"); })) check();
  return 0;
}
