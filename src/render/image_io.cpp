// Image input (stb_image for PNG/JPEG/HDR, OpenEXR) and output (libpng, OpenEXR).
#include <ImathBox.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <png.h>
#include <stb_image.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <ostream>

#include "scene_data.hpp"
#include "skin/color/color.hpp"
#include "skin/util/atomic_file.hpp"
#include "skin/util/error.hpp"
#include "skin/render/image.hpp"

namespace skin::render {

Rgb3 Image::mean(int x0, int y0, int x1, int y1) const {
  Rgb3 s;
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x, ++n) s += at(x, y);
  return n > 0 ? s / n : s;
}

std::ostream& operator<<(std::ostream& os, const Image& img) {
  return os << "Image{" << img.width << "x" << img.height << '}';
}

namespace {

void write_png(const std::string& path, const Image& img, double exposure) {
  std::FILE* fp = std::fopen(path.c_str(), "wb");
  if (!fp) throw InputError("output = '" + path + "': cannot open for writing");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(fp);
    throw InputError("output = '" + path + "': PNG write failed");
  }
  png_init_io(png, fp);
  png_set_IHDR(png, info, static_cast<png_uint_32>(img.width), static_cast<png_uint_32>(img.height),
               8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_write_info(png, info);
  const double gain = std::exp2(exposure);
  std::vector<png_byte> row(static_cast<std::size_t>(img.width) * 3);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const Rgb3 c = img.at(x, y);
      for (int k = 0; k < 3; ++k) {
        const double v = std::isfinite(c[k]) ? c[k] * gain : 0.0;
        row[static_cast<std::size_t>(x * 3 + k)] =
            static_cast<png_byte>(std::lround(255.0 * color::srgb_encode(v)));
      }
    }
    png_write_row(png, row.data());
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fclose(fp) != 0) throw InputError("output = '" + path + "': write failed");
}

void write_exr(const std::string& path, const Image& img) {
  Imf::Header header(img.width, img.height);
  const char* names[3] = {"R", "G", "B"};
  for (const char* n : names) header.channels().insert(n, Imf::Channel(Imf::FLOAT));
  Imf::FrameBuffer fb;
  const std::size_t xs = sizeof(float) * 3, ys = xs * static_cast<std::size_t>(img.width);
  auto* base = const_cast<float*>(img.rgb.data());
  for (int k = 0; k < 3; ++k)
    fb.insert(names[k], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(base + k), xs, ys));
  try {
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(img.height);
  } catch (const std::exception& e) {
    throw InputError("output = '" + path + "': EXR write failed: " + e.what());
  }
}

Image read_exr(const std::string& path) {
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    Image img(w, h);
    Imf::FrameBuffer fb;
    const std::size_t xs = sizeof(float) * 3, ys = xs * static_cast<std::size_t>(w);
    const char* names[3] = {"R", "G", "B"};
    char* origin = reinterpret_cast<char*>(img.rgb.data()) -
                   (static_cast<std::ptrdiff_t>(dw.min.x) * static_cast<std::ptrdiff_t>(xs)) -
                   (static_cast<std::ptrdiff_t>(dw.min.y) * static_cast<std::ptrdiff_t>(ys));
    for (int k = 0; k < 3; ++k)
      fb.insert(names[k], Imf::Slice(Imf::FLOAT, origin + k * static_cast<std::ptrdiff_t>(sizeof(float)), xs, ys, 1, 1, 0.0));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    return img;
  } catch (const std::exception& e) {
    throw InputError("image = '" + path + "': cannot read EXR: " + e.what());
  }
}

}  // namespace

void write_image(const std::string& path, const Image& img, double exposure) {
  require_finite("exposure", exposure);
  const std::string ext = io::extension(path);
  if (ext != "png" && ext != "exr")
    throw InputError("output = '" + path + "': unknown image format '." + ext + "', use .png or .exr");
  io::write_via_temporary(path, [&](const std::string& tmp) {
    if (ext == "png") write_png(tmp, img, exposure);
    else write_exr(tmp, img);
  });
}

Image read_image(const std::string& path, bool srgb) {
  if (!std::filesystem::is_regular_file(path))
    throw InputError("image = '" + path + "': file not found");
  const std::string ext = io::extension(path);
  if (ext == "exr") return read_exr(path);
  int w = 0, h = 0, n = 0;
  if (ext == "hdr") {
    std::unique_ptr<float, void (*)(void*)> data(stbi_loadf(path.c_str(), &w, &h, &n, 3), stbi_image_free);
    if (!data) throw InputError("image = '" + path + "': cannot read: " + stbi_failure_reason());
    Image img(w, h);
    std::copy(data.get(), data.get() + static_cast<std::ptrdiff_t>(w) * h * 3, img.rgb.begin());
    return img;
  }
  std::unique_ptr<unsigned char, void (*)(void*)> data(stbi_load(path.c_str(), &w, &h, &n, 3), stbi_image_free);
  if (!data) throw InputError("image = '" + path + "': cannot read: " + stbi_failure_reason());
  Image img(w, h);
  for (std::size_t i = 0; i < img.rgb.size(); ++i) {
    const double v = data.get()[i] / 255.0;
    img.rgb[i] = static_cast<float>(srgb ? color::srgb_decode(v) : v);
  }
  return img;
}

std::shared_ptr<Texture> load_texture(const std::string& path, bool srgb) {
  Image img = read_image(path, srgb);
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
