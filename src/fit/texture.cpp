// Albedo textures in (stb_image) and parameter maps out (OpenEXR), docs/parameter-maps.md.
#include <cmath>
#include <cstring>
#include <memory>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

#define STB_IMAGE_IMPLEMENTATION
#define STBI_FAILURE_USERMSG
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wunused-but-set-variable"
#endif
#include <stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include "skin/fit/color_fit.hpp"
#include "skin/util/atomic_file.hpp"
#include "skin/util/error.hpp"

namespace skin::fit {

Image read_albedo(const std::string& path) {
  int w = 0, h = 0, n = 0;
  Image img;
  const bool sixteen = stbi_is_16_bit(path.c_str()) != 0;
  if (sixteen) {
    std::unique_ptr<stbi_us, void (*)(void*)> data(stbi_load_16(path.c_str(), &w, &h, &n, 3), stbi_image_free);
    if (!data) throw InputError("texture '" + path + "' cannot be read: " + stbi_failure_reason());
    img.pixels.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
    for (std::size_t i = 0; i < img.pixels.size(); ++i)
      img.pixels[i] = static_cast<float>(color::srgb_decode(data.get()[i] / 65535.0));
  } else {
    std::unique_ptr<stbi_uc, void (*)(void*)> data(stbi_load(path.c_str(), &w, &h, &n, 3), stbi_image_free);
    if (!data) throw InputError("texture '" + path + "' cannot be read: " + stbi_failure_reason());
    float lut[256];
    for (int v = 0; v < 256; ++v) lut[v] = static_cast<float>(color::srgb_decode(v / 255.0));
    img.pixels.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
    for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = lut[data.get()[i]];
  }
  img.width = w;
  img.height = h;
  img.channels = 3;
  return img;
}

namespace {
const char* const kChannels[4] = {"melanin", "melanin_blend", "hemoglobin", "error"};
}

void write_parameter_maps(const ParameterMaps& maps, const std::string& path) {
  const std::size_t npix = static_cast<std::size_t>(maps.width) * static_cast<std::size_t>(maps.height);
  if (maps.width <= 0 || maps.height <= 0 || maps.melanin.size() != npix || maps.melanin_blend.size() != npix ||
      maps.hemoglobin.size() != npix || maps.error.size() != npix)
    throw InputError("parameter maps: inconsistent sizes for " + path);
  const float* planes[4] = {maps.melanin.data(), maps.melanin_blend.data(), maps.hemoglobin.data(),
                            maps.error.data()};
  io::write_via_temporary(path, [&](const std::string& tmp) {
    try {
      Imf::Header header(maps.width, maps.height);
      for (const char* c : kChannels) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
      header.insert("skin_layout", Imf::StringAttribute(
                                       "Spectral Skin parameter maps v1: melanin (C_m), melanin_blend "
                                       "(beta_m), hemoglobin (C_h), error (CIEDE2000); docs/parameter-maps.md"));
      Imf::OutputFile out(tmp.c_str(), header);
      Imf::FrameBuffer fb;
      for (int c = 0; c < 4; ++c)
        fb.insert(kChannels[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(planes[c])),
                                           sizeof(float), sizeof(float) * static_cast<std::size_t>(maps.width)));
      out.setFrameBuffer(fb);
      out.writePixels(maps.height);
    } catch (const std::exception& e) {
      throw InputError("cannot write parameter maps '" + path + "': " + e.what());
    }
  });
}

ParameterMaps read_parameter_maps(const std::string& path) {
  try {
    Imf::InputFile in(path.c_str());
    const Imath::Box2i dw = in.header().dataWindow();
    ParameterMaps maps;
    maps.width = dw.max.x - dw.min.x + 1;
    maps.height = dw.max.y - dw.min.y + 1;
    const std::size_t npix = static_cast<std::size_t>(maps.width) * static_cast<std::size_t>(maps.height);
    std::vector<float>* planes[4] = {&maps.melanin, &maps.melanin_blend, &maps.hemoglobin, &maps.error};
    Imf::FrameBuffer fb;
    for (int c = 0; c < 4; ++c) {
      if (!in.header().channels().findChannel(kChannels[c]))
        throw InputError("parameter maps '" + path + "': channel '" + kChannels[c] + "' is missing");
      planes[c]->assign(npix, 0.0f);
      char* base = reinterpret_cast<char*>(planes[c]->data()) -
                   (static_cast<std::ptrdiff_t>(dw.min.x) + static_cast<std::ptrdiff_t>(dw.min.y) * maps.width) *
                       static_cast<std::ptrdiff_t>(sizeof(float));
      fb.insert(kChannels[c], Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * static_cast<std::size_t>(maps.width)));
    }
    in.setFrameBuffer(fb);
    in.readPixels(dw.min.y, dw.max.y);
    maps.update_error_statistics();
    return maps;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError("cannot read parameter maps '" + path + "': " + e.what());
  }
}

}  // namespace skin::fit
