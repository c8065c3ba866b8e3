// Image files: stb_image reads PNG/JPEG/TGA/BMP/HDR, libpng writes PNG, OpenEXR reads and writes
// EXR (RGB images and named float planes).
#include "skin/image/image.hpp"

#include <ImathBox.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <png.h>
#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <ostream>

#include "skin/color/color.hpp"
#include "skin/util/atomic_file.hpp"
#include "skin/util/error.hpp"

namespace skin::image {

Rgb Image::mean(int x0, int y0, int x1, int y1) const {
  Rgb s;
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
      const Rgb c = img.at(x, y);
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

// One float channel of a frame buffer: `data` holds the pixel (0, 0) of the data window at
// offset 0, pixels `xs` bytes apart, rows `ys` bytes apart. OpenEXR addresses a slice by the
// pixel (0, 0) of the file's coordinates, hence the shift by the window's origin.
Imf::Slice float_slice(float* data, const Imath::Box2i& dw, std::size_t xs, std::size_t ys) {
  char* origin = reinterpret_cast<char*>(data) - static_cast<std::ptrdiff_t>(dw.min.x) * static_cast<std::ptrdiff_t>(xs) -
                 static_cast<std::ptrdiff_t>(dw.min.y) * static_cast<std::ptrdiff_t>(ys);
  return Imf::Slice(Imf::FLOAT, origin, xs, ys, 1, 1, 0.0);
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
    for (int k = 0; k < 3; ++k) fb.insert(names[k], float_slice(img.rgb.data() + k, dw, xs, ys));
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
  auto fail = [&] { return InputError("image = '" + path + "': cannot read: " + stbi_failure_reason()); };
  if (ext == "hdr") {
    std::unique_ptr<float, void (*)(void*)> data(stbi_loadf(path.c_str(), &w, &h, &n, 3), stbi_image_free);
    if (!data) throw fail();
    Image img(w, h);
    std::copy(data.get(), data.get() + static_cast<std::ptrdiff_t>(w) * h * 3, img.rgb.begin());
    return img;
  }
  auto decode = [srgb](double v) { return static_cast<float>(srgb ? color::srgb_decode(v) : v); };
  if (stbi_is_16_bit(path.c_str()) != 0) {
    std::unique_ptr<stbi_us, void (*)(void*)> data(stbi_load_16(path.c_str(), &w, &h, &n, 3), stbi_image_free);
    if (!data) throw fail();
    Image img(w, h);
    for (std::size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = decode(data.get()[i] / 65535.0);
    return img;
  }
  std::unique_ptr<stbi_uc, void (*)(void*)> data(stbi_load(path.c_str(), &w, &h, &n, 3), stbi_image_free);
  if (!data) throw fail();
  float lut[256];
  for (int v = 0; v < 256; ++v) lut[v] = decode(v / 255.0);
  Image img(w, h);
  for (std::size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = lut[data.get()[i]];
  return img;
}

void write_exr_planes(const std::string& path, const Planes& planes,
                      const std::vector<std::pair<std::string, std::string>>& attributes,
                      const std::string& what) {
  const std::size_t npix = static_cast<std::size_t>(planes.width) * static_cast<std::size_t>(planes.height);
  bool consistent = planes.width > 0 && planes.height > 0 && planes.names.size() == planes.values.size();
  for (const auto& v : planes.values) consistent = consistent && v.size() == npix;
  if (!consistent) throw InputError(what + ": inconsistent sizes for " + path);
  io::write_via_temporary(path, [&](const std::string& tmp) {
    try {
      Imf::Header header(planes.width, planes.height);
      for (const auto& name : planes.names) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
      for (const auto& [name, text] : attributes) header.insert(name, Imf::StringAttribute(text));
      Imf::OutputFile out(tmp.c_str(), header);
      Imf::FrameBuffer fb;
      for (std::size_t c = 0; c < planes.names.size(); ++c)
        fb.insert(planes.names[c],
                  Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(planes.values[c].data())),
                             sizeof(float), sizeof(float) * static_cast<std::size_t>(planes.width)));
      out.setFrameBuffer(fb);
      out.writePixels(planes.height);
    } catch (const std::exception& e) {
      throw InputError("cannot write " + what + " '" + path + "': " + e.what());
    }
  });
}

Planes read_exr_planes(const std::string& path, const std::vector<std::string>& names,
                       const std::string& what) {
  try {
    Imf::InputFile in(path.c_str());
    const Imath::Box2i dw = in.header().dataWindow();
    Planes planes;
    planes.width = dw.max.x - dw.min.x + 1;
    planes.height = dw.max.y - dw.min.y + 1;
    const std::size_t npix = static_cast<std::size_t>(planes.width) * static_cast<std::size_t>(planes.height);
    planes.names = names;
    planes.values.assign(names.size(), std::vector<float>(npix, 0.0f));
    Imf::FrameBuffer fb;
    for (std::size_t c = 0; c < names.size(); ++c) {
      if (!in.header().channels().findChannel(names[c]))
        throw InputError(what + " '" + path + "': channel '" + names[c] + "' is missing");
      fb.insert(names[c], float_slice(planes.values[c].data(), dw, sizeof(float),
                                      sizeof(float) * static_cast<std::size_t>(planes.width)));
    }
    in.setFrameBuffer(fb);
    in.readPixels(dw.min.y, dw.max.y);
    return planes;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError("cannot read " + what + " '" + path + "': " + e.what());
  }
}

}  // namespace skin::image
