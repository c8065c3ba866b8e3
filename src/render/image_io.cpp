// Textures of the renderer: images (skin::image) kept for bilinear lookup.
#include <cmath>
#include <memory>

#include "scene_data.hpp"
#include "skin/image/image.hpp"
#include "skin/util/error.hpp"

namespace skin::render {

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
