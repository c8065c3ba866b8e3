// `skin fit` end to end: JSON keys of the issue, exit code 2 and no output on bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <sys/wait.h>

#include "../temp_dir.hpp"
#include "skin/fit/color_fit.hpp"
#include "skin/fit/fit.hpp"
#include "skin/image/image.hpp"
#include <stb_image_write.h>
#include "test_params.hpp"
#include "skin_test_paths.hpp"

namespace fs = std::filesystem;

// The same suppression for this test process (the report and texture tests draw plots): LSan
// reads this hook at start-up; without a sanitizer it is never called.
extern "C" const char* __lsan_default_suppressions();
extern "C" const char* __lsan_default_suppressions() { return "leak:libfontconfig\n"; }

namespace {
struct CliRun {
  int code;
  std::string out;
};
// `prefix` goes before the command (a `cd`, environment variables); `redirect` after it.
CliRun run(const std::string& args, const std::string& prefix = "",
           const std::string& redirect = "2>/dev/null") {
  // Under -DSKIN_SANITIZE=ON the child's LeakSanitizer would report fontconfig's process-lifetime
  // cache (allocated by Cairo for plot text) and exit 1: suppress that library only.
  const std::string cmd = prefix + " LSAN_OPTIONS=suppressions=" + std::string(SKIN_SOURCE_DIR) +
                          "/tests/fit/lsan.supp " + std::string(SKIN_BINARY) + " fit " + args + " " +
                          redirect;
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  while (std::size_t n = fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  const int status = pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}
std::string temp(const std::string& name) { return (fs::temp_directory_path() / ("skin_fit_cli_" + name)).string(); }
std::string write_spectrum(const std::string& name, const skin::physics::SkinParameters& p) {
  const std::string path = temp(name);
  std::ofstream f(path);
  f << "# synthetic\nlambda_nm,R\n";
  std::vector<double> l;
  for (double x = 400; x <= 700; x += 5) l.push_back(x);
  const auto R = skin::fit::model_reflectance(p, l, skin_test::multipole_spectrum_options());
  for (std::size_t i = 0; i < l.size(); ++i) f << l[i] << "," << R[i] << "\n";
  return path;
}
}  // namespace

TEST(CliFit, SpectrumJson) {
  skin::physics::SkinParameters p;
  p.melanin = 0.04;
  p.melanin_blend = 0.4;
  p.hemoglobin = 0.02;
  const std::string in = write_spectrum("ok.csv", p), png = temp("ok.png"), fitted = temp("ok_fitted.csv");
  fs::remove(png);
  fs::remove(fitted);
  const CliRun r = run("--spectrum " + in + " --solver multipole --format json --plot " + png + " --fitted " + fitted);
  ASSERT_EQ(r.code, 0);
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["parameters"]["melanin"].get<double>(), 0.04, 1e-3);
  EXPECT_NEAR(j["parameters"]["melanin_blend"].get<double>(), 0.4, 0.01);
  EXPECT_NEAR(j["parameters"]["hemoglobin"].get<double>(), 0.02, 1e-3);
  EXPECT_TRUE(j["uncertainty"].contains("melanin"));
  EXPECT_TRUE(j["uncertainty"].contains("melanin_blend"));
  EXPECT_LT(j["rms"].get<double>(), 1e-4);
  EXPECT_EQ(j["fitted"]["wavelength_nm"].size(), 61u);
  EXPECT_EQ(j["fitted"]["R"].size(), 61u);
  EXPECT_TRUE(fs::exists(png));
  EXPECT_TRUE(fs::exists(fitted));
}

// --preview draws the four maps (melanin, melanin_blend, hemoglobin, error) in false colour,
// side by side: on a 32 x 16 texture whose colour darkens from left to right, the melanin panel
// (drawn at the texture's own 32 pixels, top left) rises from its dark blue end to its yellow
// end along a row. A preview that is not .png, or --preview without --texture, is refused before
// any work (exit 2, nothing written).
TEST(CliFit, TexturePreviewDrawsEveryMap) {
  const int w = 32, h = 16;
  std::vector<unsigned char> px(static_cast<std::size_t>(w * h * 3));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      unsigned char* c = &px[static_cast<std::size_t>((y * w + x) * 3)];
      c[0] = static_cast<unsigned char>(225 - 4 * x), c[1] = static_cast<unsigned char>(185 - 4 * x);
      c[2] = static_cast<unsigned char>(160 - 4 * x);
    }
  const std::string tex = temp("preview_albedo.png"), exr = temp("preview_maps.exr"), png = temp("preview_maps.png");
  fs::remove(exr);
  fs::remove(png);
  ASSERT_NE(stbi_write_png(tex.c_str(), w, h, 3, px.data(), w * 3), 0);
  ASSERT_EQ(run("--texture " + tex + " --solver multipole -o " + exr + " --preview " + png).code, 0);
  ASSERT_TRUE(fs::exists(exr));
  const skin::image::Image img = skin::image::read_image(png, false);
  EXPECT_EQ(img.width, 12 + 2 * (360 + 16));  // two columns of 360-pixel cells
  EXPECT_GT(img.height, 2 * (22 + h + 34));    // two rows of title, map and colour bar
  // The melanin panel: 32 x 16 pixels from (12, 48 + 22); along its middle row the blue channel
  // falls and the red-green sum rises (dark blue -> yellow) as the skin darkens.
  auto at = [&img](int x, int y, int c) { return img.rgb[(static_cast<std::size_t>(y) * static_cast<std::size_t>(img.width) + static_cast<std::size_t>(x)) * 3 + static_cast<std::size_t>(c)]; };
  const int row = 48 + 22 + h / 2;
  EXPECT_GT(at(12 + w - 2, row, 0) + at(12 + w - 2, row, 1), at(13, row, 0) + at(13, row, 1) + 0.5f);
  // Refused before any work: another extension, and without --texture.
  fs::remove(exr);
  const std::string svg = temp("preview_maps.svg");
  EXPECT_EQ(run("--texture " + tex + " --solver multipole -o " + exr + " --preview " + svg).code, 2);
  EXPECT_FALSE(fs::exists(exr));
  EXPECT_FALSE(fs::exists(svg));
  EXPECT_EQ(run("--hex c0a090 --preview " + png).code, 2);
  // The extended model's maps follow the four, then with --uncertainty the free parameters'
  // uncertainty maps: with the thickness free as well, 4 + 1 + 3 = eight panels in three columns
  // (three rows). Three free parameters keep the table small (768 nodes).
  fs::remove(png);
  ASSERT_EQ(run("--texture " + tex + " --model extended --free melanin,hemoglobin,epidermis-thickness -o " + exr +
                " --uncertainty --preview " + png).code, 0);
  const skin::image::Image ext = skin::image::read_image(png, false);
  EXPECT_EQ(ext.width, 12 + 3 * (360 + 16));  // three columns
  EXPECT_GT(ext.height, 3 * (22 + h + 34));
  const skin::fit::ParameterMaps back = skin::fit::read_parameter_maps(exr);
  EXPECT_EQ(back.more_parameters.size(), 1u);  // epidermis_thickness
  EXPECT_EQ(back.uncertainty_parameters.size(), 3u);
  EXPECT_EQ(run("--hex c0a090 --uncertainty").code, 2);  // texture fits only
}

TEST(CliFit, BadInputExitsTwoAndWritesNothing) {
  const std::string out = temp("never.json"), png = temp("never.png");
  auto check = [&](const std::string& input_text, const std::string& name) {
    const std::string in = temp(name);
    std::ofstream(in) << input_text;
    fs::remove(out);
    fs::remove(png);
    const CliRun r = run("--spectrum " + in + " -o " + out + " --plot " + png);
    EXPECT_EQ(r.code, 2) << name;
    EXPECT_FALSE(fs::exists(out)) << name;
    EXPECT_FALSE(fs::exists(png)) << name;
  };
  check("lambda_nm,R\n400,0.1\n410,x\n", "malformed.csv");
  check("lambda_nm,R\n400,0.1\n550,0.2\n700,0.3\n", "few.csv");
  std::string pct = "lambda_nm,R\n", narrow = "lambda_nm,R\n";
  for (int l = 400; l <= 700; l += 10) pct += std::to_string(l) + ",40\n";
  for (int l = 500; l <= 700; l += 10) narrow += std::to_string(l) + ",0.4\n";
  check(pct, "percent.csv");
  check(narrow, "narrow.csv");
  EXPECT_EQ(run("--spectrum /nonexistent.csv").code, 2);
  EXPECT_EQ(run("--srgb 1,2").code, 2);
  EXPECT_EQ(run("--hex zzzzzz").code, 2);
  EXPECT_EQ(run("--srgb 1,2,3 --hex 010203").code, 2);  // conflicting inputs
  EXPECT_EQ(run("--srgb 100,80,70 --includes-specular").code, 2);  // spectrum-only option
  EXPECT_EQ(run("--srgb 100,80,70 --plot " + png).code, 2);
  EXPECT_FALSE(fs::exists(png));
  EXPECT_EQ(run("--spectrum x.csv --free melanin,nonsense").code, 2);
  EXPECT_EQ(run("--texture /nonexistent.png -o " + temp("never.exr")).code, 2);
  EXPECT_FALSE(fs::exists(temp("never.exr")));
}

TEST(CliFit, HexJson) {
  const CliRun r = run("--hex c8a08c --format json");
  ASSERT_EQ(r.code, 0);
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["parameters"].contains("melanin"));
  EXPECT_TRUE(j.contains("delta_e_2000"));
  // The paper's symbols name the same parameters as the keys, in --free and in --bound.
  const CliRun keys = run("--hex c8a08c --format json --free melanin,hemoglobin --bound hemoglobin=0:0.05");
  const CliRun symbols = run("--hex c8a08c --format json --free C_m,C_h --bound C_h=0:0.05");
  ASSERT_EQ(keys.code, 0);
  ASSERT_EQ(symbols.code, 0);
  EXPECT_EQ(symbols.out, keys.out);
  EXPECT_EQ(run("--hex c8a08c --free C_m,melanin").code, 2);  // one parameter twice
  EXPECT_EQ(run("--hex c8a08c --bound C_m=0:0.1 --bound melanin=0:0.2").code, 2);
}

// The measured spectra are found through --spectra-dir, else SKIN_SPECTRA_DIR, else
// ../shared/data/skin_spectra from the current directory (no path is compiled in); a missing
// directory is one line naming it, exit 2, and nothing written.
TEST(CliFit, MeasuredReportSpectraDir) {
  const skin::test::TempDir tmp("skin_fit_cli_spectra");
  const std::string cd = "cd '" + tmp.path().string() + "' &&";
  const std::string missing = (tmp.path() / "no-such-dir").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"env -u SKIN_SPECTRA_DIR", "../shared/data/skin_spectra"},
      {"SKIN_SPECTRA_DIR='" + missing + "'", missing}};
  for (const auto& [env, named] : cases) {
    const CliRun r = run("--measured-report out", cd + " " + env, "2>&1 >/dev/null");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("'" + named + "' is not a directory"), std::string::npos) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    EXPECT_FALSE(fs::exists(tmp.path() / "out"));
  }
  // The default is shown in --help.
  EXPECT_NE(run("--help", "SKIN_SPECTRA_DIR='" + missing + "'")
                .out.find("--spectra-dir TEXT=" + missing),
            std::string::npos);
  // A directory from the environment is used: one synthetic spectrum, the report is written.
  skin::physics::SkinParameters p;
  p.melanin = 0.05;
  fs::create_directories(tmp.path() / "spectra");
  fs::copy_file(write_spectrum("measured.csv", p), tmp.path() / "spectra" / "measured.csv");
  const CliRun ok = run("--measured-report out --solver multipole",
                        cd + " SKIN_SPECTRA_DIR='" + (tmp.path() / "spectra").string() + "'");
  EXPECT_EQ(ok.code, 0) << ok.out;
  EXPECT_TRUE(fs::exists(tmp.path() / "out" / "README.md"));
  EXPECT_TRUE(fs::exists(tmp.path() / "out" / "R.png"));
  // --no-plots: the README alone; the flag belongs to the report.
  const CliRun text = run("--measured-report text --no-plots --solver multipole",
                          cd + " SKIN_SPECTRA_DIR='" + (tmp.path() / "spectra").string() + "'");
  EXPECT_EQ(text.code, 0) << text.out;
  EXPECT_TRUE(fs::exists(tmp.path() / "text" / "README.md"));
  EXPECT_FALSE(fs::exists(tmp.path() / "text" / "R.png"));
  const CliRun stray = run("--hex c8a08c --no-plots", "", "2>&1 >/dev/null");
  EXPECT_EQ(stray.code, 2);
  EXPECT_NE(stray.out.find("--no-plots requires --measured-report"), std::string::npos) << stray.out;
}
