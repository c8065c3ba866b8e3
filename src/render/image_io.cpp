// Textures of the renderer: images (skin::image) kept for bilinear lookup.
#include <cmath>
#include <memory>

#include "scene_data.hpp"
#include "skin/image/image.hpp"
#include "skin/util/atomic_file.hpp"
#include "skin/util/error.hpp"

namespace skin::render {

using skin::util::InputError;

std::shared_ptr<Texture> load_texture(const std::string& path, bool srgb) {
  image::Image img = image::read_image(path, srgb);
  if (img.width <= 0 || img.height <= 0) throw InputError("image = '" + path + "': empty image");
  auto t = std::make_shared<Texture>();
  t->path = path;
  t->width = img.width;
  t->height = img.height;
  t->rgb = std::move(img.rgb);
  return t;
}

std::shared_ptr<Texture> load_map_texture(const std::string& path, const std::string& channel,
                                          const std::string& key) {
  auto t = std::make_shared<Texture>();
  t->path = path;
  std::vector<float> plane;
  if (util::io::extension(path) == "exr") {
    const std::string name = channel.empty() ? key : channel;
    image::Planes planes = image::read_exr_planes(
        path, {name}, "parameter map (give \"channel\" to read another)");
    t->width = planes.width;
    t->height = planes.height;
    plane = std::move(planes.values[0]);
  } else {
    int c = 0;
    if (channel == "G") c = 1;
    else if (channel == "B") c = 2;
    else if (!channel.empty() && channel != "R")
      throw InputError("parameter map '" + path + "': channel '" + channel +
                       "' is not R, G or B (named channels need an OpenEXR file)");
    image::Image img = image::read_image(path, false);
    t->width = img.width;
    t->height = img.height;
    plane.resize(img.rgb.size() / 3);
    for (std::size_t i = 0; i < plane.size(); ++i) plane[i] = img.rgb[3 * i + static_cast<std::size_t>(c)];
  }
  if (t->width <= 0 || t->height <= 0) throw InputError("image = '" + path + "': empty image");
  t->rgb.assign(plane.size() * 3, 0.0f);
  for (std::size_t i = 0; i < plane.size(); ++i) {
    if (!std::isfinite(plane[i]))
      throw InputError("parameter map '" + path + "': a texel is not a finite number");
    t->rgb[3 * i] = plane[i];
  }
  return t;
}

Rgb3 Texture::texel(int x, int y) const {
  x = ((x % width) + width) % width;
  y = ((y % height) + height) % height;
  const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
  return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

Rgb3 Texture::lookup(double u, double v) const {
  // Texel centres at (i + 0.5) / width; row 0 is the top of the image, v = 0 the bottom.
  const double x = u * width - 0.5, y = (1.0 - v) * height - 0.5;
  const double fx = std::floor(x), fy = std::floor(y);
  const double tx = x - fx, ty = y - fy;
  const int ix = static_cast<int>(fx), iy = static_cast<int>(fy);
  return texel(ix, iy) * ((1 - tx) * (1 - ty)) + texel(ix + 1, iy) * (tx * (1 - ty)) +
         texel(ix, iy + 1) * ((1 - tx) * ty) + texel(ix + 1, iy + 1) * (tx * ty);
}

}  // namespace skin::render
