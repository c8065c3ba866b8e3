// Image files: stb_image reads PNG/JPEG/TGA/BMP/HDR, libpng writes PNG, OpenEXR reads and writes
// EXR (RGB images and named float planes).
#include "skin/image/image.hpp"

#include <ImathBox.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
#include <ImfStringAttribute.h>
#include <ImfThreading.h>
#include <jpeglib.h>
#include <openexr.h>
#include <png.h>
#include <stb_image.h>

#include <algorithm>
#include <cerrno>
#include <csetjmp>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <ostream>
#include <thread>
#include <tuple>

#include "skin/color/color.hpp"
#include "skin/util/atomic_file.hpp"
#include "skin/util/error.hpp"
#include "skin/util/input_file.hpp"

namespace skin::image {

using skin::util::InputError;
using skin::util::Rgb;
using skin::util::require_finite;

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

ToneMap tone_map_from_name(const std::string& name) {
  if (name == "clip") return ToneMap::clip;
  if (name == "filmic") return ToneMap::filmic;
  throw InputError("tone-map = '" + name + "' is not one of clip, filmic");
}

const char* tone_map_name(ToneMap t) { return t == ToneMap::filmic ? "filmic" : "clip"; }

double tone_curve(ToneMap t, double v) {
  if (t == ToneMap::clip) return std::clamp(v, 0.0, 1.0);
  // Hable 2010 (image.hpp): shoulder strength A, linear strength B, linear angle C, toe strength
  // D, toe numerator E, toe denominator F, linear white point W; exposure bias 2.
  constexpr double A = 0.15, B = 0.50, C = 0.10, D = 0.20, E = 0.02, F = 0.30, W = 11.2;
  const auto H = [](double x) { return (x * (A * x + C * B) + D * E) / (x * (A * x + B) + D * F) - E / F; };
  static const double white = H(W);
  if (!(v > 0)) return 0.0;
  return std::min(H(2 * v) / white, 1.0);
}

int encode_8bit(ToneMap t, double v) {
  if (!std::isfinite(v)) return 0;
  return static_cast<int>(std::lround(255.0 * color::srgb_encode(tone_curve(t, v))));
}

namespace {

// Writes to `tmp`; messages name `path`, the file the user asked for.
void write_png(const std::string& tmp, const std::string& path, const Image& img, double exposure, ToneMap tone_map) {
  std::FILE* fp = std::fopen(tmp.c_str(), "wb");
  if (!fp) throw InputError("output = '" + path + "': cannot open for writing: " + std::strerror(errno));
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(fp);
    throw InputError("output = '" + path + "': PNG write failed: " + std::strerror(errno));
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
        row[static_cast<std::size_t>(x * 3 + k)] = static_cast<png_byte>(encode_8bit(tone_map, v));
      }
    }
    png_write_row(png, row.data());
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fclose(fp) != 0) throw InputError("output = '" + path + "': write failed: " + std::strerror(errno));
}

// Width and height of an image a file declares, checked before anything is allocated: each side
// >= 1 and at most kMaxImagePixels in all (a corrupt or hostile header can declare billions).
std::pair<int, int> checked_size(long long w, long long h, const std::string& what, const std::string& path) {
  if (w < 1 || h < 1 || w > kMaxImagePixels || h > kMaxImagePixels || w * h > kMaxImagePixels)
    throw InputError(what + " = '" + path + "': declares " + std::to_string(w) + "x" + std::to_string(h) +
                     " pixels; allowed: at least 1x1 and at most " + std::to_string(kMaxImagePixels) +
                     " pixels (8192x8192)");
  return {static_cast<int>(w), static_cast<int>(h)};
}

// At most `per_byte` pixels per byte of the file: no codec packs more (PNG: deflate stops near
// 1032:1 of at least one byte per pixel, 4096; JPEG needs at least one bit per 8x8 block, 4096;
// the run lengths of BMP, TGA and Radiance HDR at most 255 pixels per 2 bytes, 128), and
// stb_image fills a truncated file's missing pixels without a word: a larger claim is a truncated
// or forged header. (OpenEXR is checked by its own core library: check_exr.)
void check_pixels_per_byte(int w, int h, const std::string& path, long long per_byte = 4096) {
  std::error_code ec;
  const auto bytes = static_cast<long long>(std::filesystem::file_size(path, ec));
  if (!ec && static_cast<long long>(w) * h > per_byte * bytes)
    throw InputError("image = '" + path + "': declares " + std::to_string(w) + "x" + std::to_string(h) +
                     " pixels, more than a file of " + std::to_string(bytes) +
                     " bytes can hold (truncated or corrupt)");
}

// The formats read_image decodes, told by their first bytes (TGA has no signature: by its
// extension alone, so that no other damaged file is read as one).
enum class Format { png, jpeg, hdr, bmp, tga, unknown };
Format format_of(const std::string& path, const std::string& ext) {
  unsigned char m[10] = {};
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return Format::unknown;
  const std::size_t n = std::fread(m, 1, sizeof m, f);
  std::fclose(f);
  if (n >= 8 && std::memcmp(m, "\x89PNG\r\n\x1a\n", 8) == 0) return Format::png;
  if (n >= 3 && m[0] == 0xFF && m[1] == 0xD8 && m[2] == 0xFF) return Format::jpeg;
  if ((n >= 10 && std::memcmp(m, "#?RADIANCE", 10) == 0) || (n >= 6 && std::memcmp(m, "#?RGBE", 6) == 0))
    return Format::hdr;
  if (n >= 2 && m[0] == 'B' && m[1] == 'M') return Format::bmp;
  if (ext == "tga") return Format::tga;
  return Format::unknown;
}

// A PNG's chunks, each inside the file, walked before stb_image reads it: stb_image allocates
// a chunk's declared length before it reads it (an 82-byte file declaring a 1.5 GB IDAT held the
// fuzzer for 12 s under ASan).
void check_png_chunks(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  const auto size = static_cast<unsigned long long>(std::filesystem::file_size(path, ec));
  if (!in || ec) throw InputError("image = '" + path + "': cannot read");
  unsigned long long at = 8;
  while (at + 12 <= size) {
    unsigned char head[8];
    in.seekg(static_cast<std::streamoff>(at));
    if (!in.read(reinterpret_cast<char*>(head), 8)) break;
    const unsigned long long length = (static_cast<unsigned long long>(head[0]) << 24) | (head[1] << 16) |
                                      (head[2] << 8) | head[3];
    if (at + 12 + length > size)
      throw InputError("image = '" + path + "': a PNG chunk of " + std::to_string(length) +
                       " bytes runs past the end of the file (truncated or corrupt)");
    if (std::memcmp(head + 4, "IEND", 4) == 0) return;
    at += 12 + length;
  }
}

// The size of an EXR file's data window, checked.
std::pair<int, int> checked_size(const Imath::Box2i& dw, const std::string& what, const std::string& path) {
  return checked_size(static_cast<long long>(dw.max.x) - dw.min.x + 1,
                      static_cast<long long>(dw.max.y) - dw.min.y + 1, what, path);
}

// One float channel of a frame buffer: `data` holds the pixel (0, 0) of the data window at
// offset 0, pixels `xs` bytes apart, rows `ys` bytes apart. OpenEXR addresses a slice by the
// pixel (0, 0) of the file's coordinates, hence the shift by the window's origin.
Imf::Slice float_slice(float* data, const Imath::Box2i& dw, std::size_t xs, std::size_t ys) {
  char* origin = reinterpret_cast<char*>(data) - static_cast<std::ptrdiff_t>(dw.min.x) * static_cast<std::ptrdiff_t>(xs) -
                 static_cast<std::ptrdiff_t>(dw.min.y) * static_cast<std::ptrdiff_t>(ys);
  return Imf::Slice(Imf::FLOAT, origin, xs, ys, 1, 1, 0.0);
}

// Writes an OpenEXR file of `header` to `tmp`, the pixels from `fb`; messages name `shown`.
// OpenEXR writes the table of line offsets when the file object is destroyed and reports no
// error from there, so the stream is ours and its state is checked after that: a write that
// failed late (a full disk) never passes for a complete file.
// OpenEXR compresses blocks of scanlines in parallel on its own thread pool, which is empty
// unless given threads: a 4096 x 4096 map of four float channels took 2.2 s to write on one
// thread of this project's 2-core machine. Twice as many threads as cores keep the cores busy
// while the writing thread waits on the file: seven such channels (the extended model's maps,
// 173 MB) took 6.7 s on one thread, 4.3 s on two, 3.6 s on four. The bytes written do not
// depend on it. (Readers below pass 0 threads explicitly.)
void use_exr_threads() {
  static std::once_flag once;
  std::call_once(once, [] { Imf::setGlobalThreadCount(static_cast<int>(2 * std::max(1u, std::thread::hardware_concurrency()))); });
}

void write_exr_file(const std::string& tmp, const std::string& shown, const Imf::Header& header,
                    const Imf::FrameBuffer& fb) {
  use_exr_threads();
  std::ofstream os(tmp, std::ios::binary | std::ios::trunc);
  if (!os) throw InputError(shown + ": cannot open for writing: " + std::strerror(errno));
  errno = 0;
  try {
    Imf::StdOFStream stream(os, tmp.c_str());
    {
      Imf::OutputFile file(stream, header);
      file.setFrameBuffer(fb);
      file.writePixels(header.dataWindow().max.y - header.dataWindow().min.y + 1);
    }
    os.close();
  } catch (const std::exception& e) {
    throw InputError(shown + ": EXR write failed: " + e.what());
  }
  if (os.fail())
    throw InputError(shown + ": EXR write failed" + (errno ? std::string(": ") + std::strerror(errno) : ""));
}

void write_exr(const std::string& tmp, const std::string& path, const Image& img) {
  Imf::Header header(img.width, img.height);
  const char* names[3] = {"R", "G", "B"};
  for (const char* n : names) header.channels().insert(n, Imf::Channel(Imf::FLOAT));
  Imf::FrameBuffer fb;
  const std::size_t xs = sizeof(float) * 3, ys = xs * static_cast<std::size_t>(img.width);
  auto* base = const_cast<float*>(img.rgb.data());
  for (int k = 0; k < 3; ++k)
    fb.insert(names[k], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(base + k), xs, ys));
  write_exr_file(tmp, "output = '" + path + "'", header, fb);
}

// JPEG through libjpeg-turbo, the field's decoder (continuously fuzzed upstream; stb_image's
// JPEG decoder read out of bounds on a fuzzed file). Its errors and its warnings (corrupt or
// truncated data, which it would otherwise fill with grey) end the read by longjmp back to
// the setjmp of the phase that failed; each phase touches only plain C data after its setjmp.
struct JpegError {
  jpeg_error_mgr mgr;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

[[noreturn]] void jpeg_fail(j_common_ptr c) {
  auto* e = reinterpret_cast<JpegError*>(c->err);
  (*c->err->format_message)(c, e->message);
  std::longjmp(e->jump, 1);
}

void jpeg_warning(j_common_ptr c, int level) {
  if (level < 0) jpeg_fail(c);  // a warning: corrupt data (level >= 0: trace messages)
}

bool is_jpeg(const std::string& path) {
  unsigned char magic[3] = {0, 0, 0};
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return false;
  const std::size_t n = std::fread(magic, 1, 3, f);
  std::fclose(f);
  return n == 3 && magic[0] == 0xFF && magic[1] == 0xD8 && magic[2] == 0xFF;
}

// Phase 1: the header (false on an error, with the message in err).
bool jpeg_header(jpeg_decompress_struct* d, JpegError* err, std::FILE* f, int* w, int* h) {
  if (setjmp(err->jump)) return false;
  jpeg_create_decompress(d);
  jpeg_stdio_src(d, f);
  jpeg_read_header(d, TRUE);
  d->out_color_space = JCS_RGB;
  *w = static_cast<int>(d->image_width);
  *h = static_cast<int>(d->image_height);
  return true;
}

// Phase 2: the pixels, into rgb (w x h x 3 bytes, allocated by the caller).
bool jpeg_pixels(jpeg_decompress_struct* d, JpegError* err, unsigned char* rgb, std::size_t row_bytes) {
  if (setjmp(err->jump)) return false;
  jpeg_start_decompress(d);
  if (d->output_components != 3) {
    std::snprintf(err->message, sizeof err->message, "%d colour components, expected 3", d->output_components);
    return false;
  }
  while (d->output_scanline < d->output_height) {
    JSAMPROW row = rgb + static_cast<std::size_t>(d->output_scanline) * row_bytes;
    jpeg_read_scanlines(d, &row, 1);
  }
  jpeg_finish_decompress(d);
  return true;
}

Image read_jpeg(const std::string& path, bool srgb) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw InputError("image = '" + path + "': cannot open: " + std::strerror(errno));
  jpeg_decompress_struct d;
  JpegError err;
  err.message[0] = '\0';
  d.err = jpeg_std_error(&err.mgr);
  err.mgr.error_exit = jpeg_fail;
  err.mgr.emit_message = jpeg_warning;
  auto fail = [&](const char* what) {
    jpeg_destroy_decompress(&d);
    std::fclose(f);
    std::string m = err.message;
    for (char& c : m)
      if (static_cast<unsigned char>(c) < 0x20) c = ' ';
    return InputError("image = '" + path + "': cannot read JPEG " + what + ": " + (m.empty() ? "corrupt data" : m));
  };
  int w = 0, h = 0;
  if (!jpeg_header(&d, &err, f, &w, &h)) throw fail("header");
  try {
    checked_size(w, h, "image", path);
    check_pixels_per_byte(w, h, path);
  } catch (const InputError&) {
    jpeg_destroy_decompress(&d);
    std::fclose(f);
    throw;
  }
  const std::size_t row_bytes = static_cast<std::size_t>(w) * 3;
  std::vector<unsigned char> rgb(row_bytes * static_cast<std::size_t>(h));
  if (!jpeg_pixels(&d, &err, rgb.data(), row_bytes)) throw fail("data");
  jpeg_destroy_decompress(&d);
  std::fclose(f);
  float lut[256];
  for (int v = 0; v < 256; ++v) lut[v] = static_cast<float>(srgb ? color::srgb_decode(v / 255.0) : v / 255.0);
  Image img(w, h);
  for (std::size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = lut[rgb[i]];
  return img;
}

// What an OpenEXR file can hold, checked by OpenEXR's own core library before the C++ reader
// allocates anything (a header's attribute sizes, the data window, the chunk table): the image
// at most 8192 x 8192 (OpenEXR's maximum image and tile size), one part, flat (not deep), at most
// kMaxExrChannels channels, every chunk of the first level inside the file with a size the
// file can hold, and at most 4096 pixels per byte of the file (as for the other formats; a flat
// DWA image packs more, a real texture far less). Costs one read of the header and of the chunk
// table: milliseconds and kilobytes whatever the file declares.
constexpr int kMaxExrChannels = 256;

void check_exr(const std::string& path, const std::string& what) {
  std::error_code ec;
  const auto file_bytes = static_cast<long long>(std::filesystem::file_size(path, ec));
  if (ec) throw InputError(what + " = '" + path + "': cannot read: " + ec.message());
  struct Context {
    exr_context_t ctx = nullptr;
    std::string message;
    ~Context() { exr_finish(&ctx); }
  } c;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.user_data = &c.message;
  init.error_handler_fn = [](exr_const_context_t ctx, exr_result_t code, const char* msg) {
    void* user = nullptr;
    exr_get_user_data(ctx, &user);
    auto* m = static_cast<std::string*>(user);
    if (m && m->empty()) *m = msg ? msg : exr_get_default_error_message(code);
  };
  init.max_image_width = init.max_image_height = 8192;
  init.max_tile_width = init.max_tile_height = 8192;
  init.flags = EXR_CONTEXT_FLAG_STRICT_HEADER;
  auto fail = [&](const std::string& why) {
    std::string m = why;
    for (char& ch : m)
      if (static_cast<unsigned char>(ch) < 0x20) ch = ' ';
    return InputError(what + " = '" + path + "': cannot read EXR: " + m);
  };
  auto check = [&](exr_result_t r) {
    if (r != EXR_ERR_SUCCESS) throw fail(c.message.empty() ? exr_get_default_error_message(r) : c.message);
  };
  // (exr_start_read returns success on a header it could only partly parse: its errors count.)
  check(exr_start_read(&c.ctx, path.c_str(), &init));
  if (!c.message.empty()) throw fail(c.message);
  int parts = 0;
  check(exr_get_count(c.ctx, &parts));
  if (parts != 1) throw fail("has " + std::to_string(parts) + " parts; allowed: a single-part image");
  exr_storage_t storage{};
  check(exr_get_storage(c.ctx, 0, &storage));
  if (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED)
    throw fail("deep data; allowed: a flat scanline or tiled image");
  exr_attr_box2i_t dw{};
  check(exr_get_data_window(c.ctx, 0, &dw));
  const auto [w, h] = checked_size(static_cast<long long>(dw.max.x) - dw.min.x + 1,
                                   static_cast<long long>(dw.max.y) - dw.min.y + 1, what, path);
  if (static_cast<long long>(w) * h > 4096 * file_bytes)
    throw InputError(what + " = '" + path + "': declares " + std::to_string(w) + "x" + std::to_string(h) +
                     " pixels, more than a file of " + std::to_string(file_bytes) +
                     " bytes can hold (truncated or corrupt)");
  const exr_attr_chlist_t* channels = nullptr;
  check(exr_get_channels(c.ctx, 0, &channels));
  if (!channels || channels->num_channels < 1 || channels->num_channels > kMaxExrChannels)
    throw fail("has " + std::to_string(channels ? channels->num_channels : 0) + " channels; allowed: 1 to " +
               std::to_string(kMaxExrChannels));
  // Every chunk of the image (level 0 of a tiled one) inside the file.
  unsigned long long packed = 0;
  auto add = [&](const exr_chunk_info_t& ci) {
    packed += ci.packed_size;
    const auto size = static_cast<unsigned long long>(file_bytes);
    if (ci.packed_size == 0 || ci.data_offset > size || ci.packed_size > size - ci.data_offset || packed > size)
      throw fail("a pixel block lies outside the file (truncated or corrupt)");
  };
  exr_chunk_info_t ci{};
  if (storage == EXR_STORAGE_SCANLINE) {
    int32_t lines = 0;
    check(exr_get_scanlines_per_chunk(c.ctx, 0, &lines));
    if (lines < 1) throw fail("invalid scanlines per block");
    for (long long y = dw.min.y; y <= dw.max.y; y += lines) {
      check(exr_read_scanline_chunk_info(c.ctx, 0, static_cast<int>(y), &ci));
      add(ci);
    }
  } else {
    int32_t tw = 0, th = 0;
    check(exr_get_tile_sizes(c.ctx, 0, 0, 0, &tw, &th));
    if (tw < 1 || th < 1) throw fail("invalid tile size");
    const int nx = (w + tw - 1) / tw, ny = (h + th - 1) / th;
    for (int ty = 0; ty < ny; ++ty)
      for (int tx = 0; tx < nx; ++tx) {
        check(exr_read_tile_chunk_info(c.ctx, 0, tx, ty, 0, 0, &ci));
        add(ci);
      }
  }
}

// Reads the float channels `names` of an EXR file (already checked by check_exr) band by band of
// at most 64 rows, appending each band to `out` (pixel-interleaved when `interleaved`, one vector
// per channel otherwise): memory grows with the data that actually decodes, so a truncated file
// fails before it costs the declared image's size.
// A channel missing from the file reads as 0, or is refused when `required`.
void read_exr_bands(const std::string& path, const std::vector<std::string>& names, bool interleaved,
                    bool required, const std::string& what, int* width, int* height,
                    std::vector<std::vector<float>>& out) {
  // Read on the calling thread (0 threads, as before the writer had any): the path the fuzzers
  // cover, and a read is band by band anyway.
  Imf::InputFile file(path.c_str(), 0);
  if (required)
    for (const auto& name : names)
      if (!file.header().channels().findChannel(name))
        throw InputError(what + " '" + path + "': channel '" + name + "' is missing");
  const Imath::Box2i dw = file.header().dataWindow();
  const auto [w, h] = checked_size(dw, what, path);
  *width = w;
  *height = h;
  const std::size_t nc = names.size(), row = static_cast<std::size_t>(w) * (interleaved ? nc : 1);
  out.assign(interleaved ? 1 : nc, {});
  for (auto& v : out) v.reserve(row * static_cast<std::size_t>(h));
  constexpr int kBand = 64;
  std::vector<float> band;
  for (int y0 = dw.min.y; y0 <= dw.max.y; y0 += kBand) {
    const int y1 = std::min(dw.max.y, y0 + kBand - 1), rows = y1 - y0 + 1;
    band.assign(row * static_cast<std::size_t>(rows) * (interleaved ? 1 : nc), 0.0f);
    Imf::FrameBuffer fb;
    const std::size_t xs = sizeof(float) * (interleaved ? nc : 1), ys = sizeof(float) * row;
    Imath::Box2i window = dw;
    window.min.y = y0;
    for (std::size_t k = 0; k < nc; ++k) {
      float* base = interleaved ? band.data() + k : band.data() + k * row * static_cast<std::size_t>(rows);
      fb.insert(names[k], float_slice(base, window, xs, ys));
    }
    file.setFrameBuffer(fb);
    file.readPixels(y0, y1);
    const std::size_t n = row * static_cast<std::size_t>(rows);
    for (std::size_t k = 0; k < out.size(); ++k)
      out[k].insert(out[k].end(), band.begin() + static_cast<std::ptrdiff_t>(k * n),
                    band.begin() + static_cast<std::ptrdiff_t>((k + 1) * n));
  }
}

Image read_exr(const std::string& path) {
  check_exr(path, "image");
  try {
    std::vector<std::vector<float>> data;
    Image img;
    read_exr_bands(path, {"R", "G", "B"}, true, false, "image", &img.width, &img.height, data);
    img.rgb = std::move(data.front());
    return img;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError("image = '" + path + "': cannot read EXR: " + e.what());
  }
}

}  // namespace

void write_image(const std::string& path, const Image& img, double exposure, ToneMap tone_map) {
  require_finite("exposure", exposure);
  const std::string ext = util::io::extension(path);
  if (ext != "png" && ext != "exr")
    throw InputError("output = '" + path + "': unknown image format '." + ext + "', use .png or .exr");
  util::io::write_via_temporary(path, [&](const std::string& tmp) {
    if (ext == "png") write_png(tmp, path, img, exposure, tone_map);
    else write_exr(tmp, path, img);
  });
}

Image read_image(const std::string& path, bool srgb) {
  util::io::check_input_file(path, "image");
  const std::string ext = util::io::extension(path);
  if (ext == "exr") return read_exr(path);
  const Format format = format_of(path, ext);
  if (format == Format::jpeg) return read_jpeg(path, srgb);  // (stb never sees a JPEG)
  if (format == Format::unknown)
    throw InputError("image = '" + path + "': not a PNG, JPEG, Radiance HDR or BMP file (by its first bytes), nor an "
                     "OpenEXR or TGA file (by its extension .exr, .tga)");
  if (format == Format::png) check_png_chunks(path);
  int w = 0, h = 0, n = 0;
  auto fail = [&] { return InputError("image = '" + path + "': cannot read: " + stbi_failure_reason()); };
  if (stbi_info(path.c_str(), &w, &h, &n) == 0) throw fail();
  checked_size(w, h, "image", path);
  check_pixels_per_byte(w, h, path, format == Format::png ? 4096 : 128);
  if (format == Format::hdr) {
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
  if (planes.names.size() != planes.values.size()) throw InputError(what + ": inconsistent sizes for " + path);
  std::vector<PlaneView> views;
  for (std::size_t c = 0; c < planes.names.size(); ++c) views.push_back({planes.names[c], &planes.values[c]});
  write_exr_planes(path, planes.width, planes.height, views, attributes, what);
}

void write_exr_planes(const std::string& path, int width, int height, const std::vector<PlaneView>& planes,
                      const std::vector<std::pair<std::string, std::string>>& attributes,
                      const std::string& what) {
  const std::size_t npix = static_cast<std::size_t>(std::max(width, 0)) * static_cast<std::size_t>(std::max(height, 0));
  bool consistent = width > 0 && height > 0 && !planes.empty();
  for (const auto& v : planes) consistent = consistent && v.values && v.values->size() == npix;
  if (!consistent) throw InputError(what + ": inconsistent sizes for " + path);
  util::io::write_via_temporary(path, [&](const std::string& tmp) {
    Imf::Header header(width, height);
    // ZIP at zlib's fastest level: the extended model's seven 4096 x 4096 float maps compress
    // in 5.1 s of one core instead of 6.7 s at OpenEXR's default level 4, into a file 6 % larger
    // (183 MB, not 173); any EXR reader inflates either.
    header.zipCompressionLevel() = 1;
    for (const auto& v : planes) header.channels().insert(v.name, Imf::Channel(Imf::FLOAT));
    for (const auto& [name, text] : attributes) header.insert(name, Imf::StringAttribute(text));
    Imf::FrameBuffer fb;
    for (const auto& v : planes)
      fb.insert(v.name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(v.values->data())),
                                   sizeof(float), sizeof(float) * static_cast<std::size_t>(width)));
    write_exr_file(tmp, what + " = '" + path + "'", header, fb);
  });
}

Planes read_exr_planes(const std::string& path, const std::vector<std::string>& names,
                       const std::string& what) {
  util::io::check_input_file(path, what);
  check_exr(path, what);
  try {
    Planes planes;
    planes.names = names;
    read_exr_bands(path, names, false, true, what, &planes.width, &planes.height, planes.values);
    return planes;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError("cannot read " + what + " '" + path + "': " + e.what());
  }
}

std::vector<std::string> exr_channel_names(const std::string& path, const std::string& what) {
  util::io::check_input_file(path, what);
  check_exr(path, what);
  try {
    Imf::InputFile file(path.c_str(), 0);
    std::vector<std::string> names;
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it)
      names.emplace_back(it.name());
    return names;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError("cannot read " + what + " '" + path + "': " + e.what());
  }
}

}  // namespace skin::image
