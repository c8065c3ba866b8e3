// Image files (include/skin/image/image.hpp): EXR round trips are exact, PNG round trips are
// within the 8-bit quantisation of the sRGB curve, planes keep their names and values, bad input
// is an InputError naming the file, and a failed write leaves the target untouched.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <sys/resource.h>

#include "skin/image/image.hpp"
#include "skin/util/error.hpp"

namespace skin::image {

using skin::util::InputError;
using skin::util::Rgb;

namespace {

namespace fs = std::filesystem;

class ImageFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("skin_image_test_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

Image gradient(int w, int h) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.set(x, y, {x / (w - 1.0), y / (h - 1.0), 0.25 + 0.01 * x});
  return img;
}

// Writes img to `file` and reads it back (same size, or the test stops).
Image round_trip(const std::string& file, const Image& img) {
  write_image(file, img);
  Image back = read_image(file);
  EXPECT_EQ(back.width, img.width);
  EXPECT_EQ(back.height, img.height);
  if (back.rgb.size() != img.rgb.size()) throw std::runtime_error("round trip changed the size");
  return back;
}

TEST_F(ImageFiles, ExrRoundTripIsExact) {
  const Image img = gradient(7, 5);
  EXPECT_EQ(round_trip(path("a.exr"), img).rgb, img.rgb);
}

TEST_F(ImageFiles, PngRoundTripWithinEightBitQuantisation) {
  const Image img = gradient(9, 4);
  const Image back = round_trip(path("a.png"), img);
  // Half a code value of the sRGB curve: its slope is at most 12.92, so a linear error of at
  // most 0.5 / 255 / 12.92 near black, and 0.5 / 255 times the inverse curve's slope (< 2.4)
  // elsewhere.
  for (std::size_t i = 0; i < img.rgb.size(); ++i) EXPECT_NEAR(back.rgb[i], img.rgb[i], 2.4 * 0.5 / 255) << i;
  // Exposure: +1 stop doubles the linear value before encoding.
  Image dark(1, 1);
  dark.set(0, 0, {0.1, 0.2, 0.3});
  write_image(path("b.png"), dark, 1.0);
  const Rgb c = read_image(path("b.png")).at(0, 0);
  EXPECT_NEAR(c.r, 0.2, 2e-3);
  EXPECT_NEAR(c.b, 0.6, 4e-3);
  // Without the sRGB decode, the stored code values come back as they are (0-1).
  EXPECT_NEAR(read_image(path("b.png"), false).at(0, 0).r, std::round(255 * 0.4845) / 255, 1.5e-3);
}

TEST_F(ImageFiles, PlanesKeepNamesAndValues) {
  Planes p{3, 2, {"melanin", "error"}, {{1, 2, 3, 4, 5, 6}, {0.5f, 0, 0, 0, 0, 1e-7f}}};
  write_exr_planes(path("p.exr"), p, {{"skin_layout", "test"}}, "test maps");
  const Planes back = read_exr_planes(path("p.exr"), {"error", "melanin"}, "test maps");
  ASSERT_EQ(back.width, 3);
  ASSERT_EQ(back.height, 2);
  EXPECT_EQ(back.values[0], p.values[1]);
  EXPECT_EQ(back.values[1], p.values[0]);
  try {
    read_exr_planes(path("p.exr"), {"hemoglobin"}, "test maps");
    FAIL() << "a missing channel must throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("channel 'hemoglobin' is missing"), std::string::npos) << e.what();
  }
  Planes bad = p;
  bad.values[1].pop_back();
  EXPECT_THROW(write_exr_planes(path("q.exr"), bad, {}, "test maps"), InputError);
  EXPECT_FALSE(fs::exists(path("q.exr")));
}

// Read in bands of 64 rows: an image of several bands, and one whose last band is partial, reads
// back exactly.
TEST_F(ImageFiles, TallExrImagesReadBandByBand) {
  const Image img = gradient(5, 150);
  EXPECT_EQ(round_trip(path("tall.exr"), img).rgb, img.rgb);
  Planes p{2, 129, {"melanin"}, {std::vector<float>(2 * 129)}};
  for (std::size_t i = 0; i < p.values[0].size(); ++i) p.values[0][i] = static_cast<float>(i);
  write_exr_planes(path("tall-planes.exr"), p, {}, "test maps");
  EXPECT_EQ(read_exr_planes(path("tall-planes.exr"), {"melanin"}, "test maps").values[0], p.values[0]);
}

std::string slurp(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
void spit(const std::string& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
}
long peak_rss_kb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

// A damaged or hostile EXR is refused before anything of the size it declares is allocated
// (fuzz/regressions/fuzz_parameter_maps: a string attribute declaring 1.98 GB took 1.9 GB and
// 7.7 s before OpenEXR's C++ reader found the end of the file). Each case: one line naming the
// file, and the process' peak memory grows by less than 64 MB (without the checks: 1.9 GB for
// the attribute, 1 GB of planes for the data window).
TEST_F(ImageFiles, DamagedExrIsRefusedBeforeItsDeclaredSizeIsAllocated) {
  Planes p{8, 8, {"melanin"}, {std::vector<float>(64, 0.25f)}};
  write_exr_planes(path("ok.exr"), p, {{"skin_layout", "test"}}, "test maps");
  const std::string good = slurp(path("ok.exr"));
  auto refused = [&](const std::string& name, const std::string& bytes, const std::string& what) {
    spit(path(name), bytes);
    const long before = peak_rss_kb();
    for (const bool planes : {true, false}) {
      try {
        if (planes) read_exr_planes(path(name), {"melanin"}, "test maps");
        else read_image(path(name));
        ADD_FAILURE() << name << ": accepted";
      } catch (const InputError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find(name), std::string::npos) << m;
        EXPECT_NE(m.find(what), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
      }
    }
    EXPECT_LT(peak_rss_kb() - before, 64 * 1024) << name;
  };
  // The string attribute's size (after "skin_layout\0string\0") set to 0x76000000 bytes.
  std::string bad = good;
  const std::string key = std::string("skin_layout") + '\0' + "string" + '\0';
  ASSERT_NE(bad.find(key), std::string::npos);
  bad.replace(bad.find(key) + key.size(), 4, std::string("\x00\x00\x00\x76", 4));
  refused("attribute.exr", bad, "Invalid size");
  // The data window's maximum (after "dataWindow\0box2i\0" and the size) set to 8191 x 8191:
  // 8 x 8 pixels of data for an image of 256 MB a plane.
  bad = good;
  const std::string dw = std::string("dataWindow") + '\0' + "box2i" + '\0';
  ASSERT_NE(bad.find(dw), std::string::npos);
  bad.replace(bad.find(dw) + dw.size() + 4 + 8, 8, std::string("\xff\x1f\x00\x00\xff\x1f\x00\x00", 8));
  refused("window.exr", bad, "a file of");
  // Truncated inside the pixels.
  refused("truncated.exr", good.substr(0, good.size() - 40), "cannot read EXR");
}

// A PNG whose chunk runs past the end of the file is refused before stb_image allocates the
// chunk's declared length (an 82-byte file declaring a 1.5 GB IDAT held the fuzzer 12 s), and a
// file that is none of the formats read is refused by its first bytes (stb_image read a damaged
// .jpg without a JPEG signature as a TGA of 7710 x 99 pixels).
TEST_F(ImageFiles, PngChunksAndFormatsAreCheckedBeforeDecoding) {
  write_image(path("ok.png"), gradient(4, 4));
  std::string png = slurp(path("ok.png"));
  const std::size_t idat = png.find("IDAT");
  ASSERT_NE(idat, std::string::npos);
  png.replace(idat - 4, 4, std::string("\x5e\x63\x00\x19", 4));
  spit(path("long-chunk.png"), png);
  const long before = peak_rss_kb();
  try {
    read_image(path("long-chunk.png"));
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a PNG chunk of 1583546393 bytes runs past the end of the file"),
              std::string::npos) << e.what();
  }
  EXPECT_LT(peak_rss_kb() - before, 64 * 1024);
  spit(path("junk.jpg"), std::string("\xff\x00\x03\x65", 4) + std::string(100, '\xf5'));
  try {
    read_image(path("junk.jpg"));
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("junk.jpg': not a PNG, JPEG, Radiance HDR or BMP file"), std::string::npos)
        << e.what();
  }
}

TEST_F(ImageFiles, BadInputNamesTheFileAndLeavesTargetsUntouched) {
  try {
    read_image(path("missing.png"));
    FAIL() << "a missing file must throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.png"), std::string::npos) << e.what();
  }
  { std::ofstream(path("junk.png")) << "not a png"; }
  EXPECT_THROW(read_image(path("junk.png")), InputError);
  EXPECT_THROW(write_image(path("a.tiff"), gradient(2, 2)), InputError);
  { std::ofstream(path("keep.png")) << "old"; }
  EXPECT_THROW(write_image(path("keep.png"), gradient(2, 2), std::nan("")), InputError);
  std::ifstream in(path("keep.png"));
  std::stringstream s;
  s << in.rdbuf();
  EXPECT_EQ(s.str(), "old");
}

// The tone curves of PNG output (image.hpp): both map 0 to 0, never decrease and stay in
// [0, 1]; clip is the identity on [0, 1]; filmic takes Hable's published constants (A 0.15,
// B 0.50, C 0.10, D 0.20, E 0.02, F 0.30, W 11.2, exposure bias 2): the values below are that
// formula evaluated independently (Python, double precision).
TEST(ToneMap, CurvesAreMonotonicAndFixZero) {
  for (ToneMap t : {ToneMap::clip, ToneMap::filmic}) {
    SCOPED_TRACE(tone_map_name(t));
    EXPECT_EQ(tone_curve(t, 0.0), 0.0);
    EXPECT_EQ(tone_curve(t, -1.0), 0.0);
    EXPECT_EQ(encode_8bit(t, 0.0), 0);
    EXPECT_EQ(encode_8bit(t, std::nan("")), 0);
    double prev = 0;
    for (int i = 1; i <= 4000; ++i) {
      const double v = i * 0.005, y = tone_curve(t, v);
      EXPECT_GE(y, prev) << "at v = " << v;
      EXPECT_LE(y, 1.0);
      prev = y;
    }
    EXPECT_EQ(tone_curve(t, 100.0), 1.0);
    EXPECT_EQ(encode_8bit(t, 100.0), 255);
    EXPECT_EQ(tone_map_from_name(tone_map_name(t)), t);
  }
  EXPECT_THROW(tone_map_from_name("aces"), InputError);
}

TEST(ToneMap, ClipIsPlainSrgb) {
  EXPECT_EQ(tone_curve(ToneMap::clip, 0.25), 0.25);
  EXPECT_EQ(encode_8bit(ToneMap::clip, 1.0), 255);
  EXPECT_EQ(encode_8bit(ToneMap::clip, 2.0), 255);
  EXPECT_EQ(encode_8bit(ToneMap::clip, 0.18), 118);  // 255 x (1.055 x 0.18^(1/2.4) - 0.055)
  EXPECT_EQ(encode_8bit(ToneMap::clip, 0.5), 188);
}

TEST(ToneMap, FilmicKnownValues) {
  EXPECT_NEAR(tone_curve(ToneMap::filmic, 0.01), 0.007663655153138008, 1e-12);
  EXPECT_NEAR(tone_curve(ToneMap::filmic, 0.18), 0.12833844885562762, 1e-12);
  EXPECT_NEAR(tone_curve(ToneMap::filmic, 0.5), 0.304300561467247, 1e-12);
  EXPECT_NEAR(tone_curve(ToneMap::filmic, 1.0), 0.49291854599116447, 1e-12);
  EXPECT_NEAR(tone_curve(ToneMap::filmic, 2.0), 0.7132380109726539, 1e-12);
  EXPECT_NEAR(tone_curve(ToneMap::filmic, 4.0), 0.9180300792727346, 1e-12);
  EXPECT_NEAR(tone_curve(ToneMap::filmic, 5.6), 1.0, 1e-12);  // the white point W / 2
  EXPECT_EQ(tone_curve(ToneMap::filmic, 10.0), 1.0);           // H keeps rising past W: clamped
  // Slope at 0: B (C - E / F) / (D F) x 2 / H(W) = 0.7661.
  EXPECT_NEAR(tone_curve(ToneMap::filmic, 1e-9) / 1e-9, 0.7661468, 1e-6);
  EXPECT_EQ(encode_8bit(ToneMap::filmic, 0.18), 100);
  EXPECT_EQ(encode_8bit(ToneMap::filmic, 1.0), 186);
}

TEST_F(ImageFiles, PngFollowsTheToneCurve) {
  Image img(2, 1);
  img.set(0, 0, {1.0, 0.18, 4.0});
  img.set(1, 0, {0.0, 0.5, 20.0});
  write_image(path("f.png"), img, 0.0, ToneMap::filmic);
  const Image back = read_image(path("f.png"), false);
  const double codes[] = {186, 100, static_cast<double>(encode_8bit(ToneMap::filmic, 4.0)), 0,
                          static_cast<double>(encode_8bit(ToneMap::filmic, 0.5)), 255};
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(back.rgb[static_cast<std::size_t>(i)] * 255.0, codes[i], 1e-3) << i;
}

TEST(Image, MeanAndPrinting) {
  Image img(2, 2);
  img.set(0, 0, {1, 0, 0});
  img.set(1, 1, {0, 0, 1});
  EXPECT_EQ(img.mean(0, 0, 2, 2), (Rgb{0.25, 0, 0.25}));
  EXPECT_EQ(img.mean(0, 0, 0, 0), Rgb{});
  std::ostringstream os;
  os << img;
  EXPECT_EQ(os.str(), "Image{2x2}");
}

}  // namespace
}  // namespace skin::image
