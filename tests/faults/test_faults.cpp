// Faults survived with nothing lost: a write onto a full disk, inputs that are missing,
// unreadable, truncated or of the wrong type, and requests too large to run. Each fails with one
// line naming the file (or the request) and what is wrong, exit 2, no temporary file left and
// an existing output untouched.
#include <sys/mount.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "process.hpp"
#include "skin/image/image.hpp"
#include "skin_test_paths.hpp"

namespace {
using namespace skin_test;

const std::string kPrevious = "previous output, must survive\n";
const std::string kFuzzAssets = SKIN_SOURCE_DIR "/fuzz/assets";

class Faults : public InDir {
 protected:
  // Runs `args`, which must fail with one line containing each of `needles`, exit 2, and leave
  // the directory as it was (outputs named in `args` never appear or keep their old content).
  void expect_one_line_failure(const std::string& args, const std::vector<std::string>& needles,
                               const Spawn* spawn = nullptr) {
    SCOPED_TRACE("skin " + args);
    const std::vector<std::string> before = listing();
    // Contents (of files up to 1 MiB; larger ones, the sparse 2 GiB CSV, by size).
    auto content = [this](const std::string& n) {
      const fs::path p = dir_ / n;
      if (!fs::is_regular_file(p)) return std::string();
      return fs::file_size(p) > (1u << 20) ? std::to_string(fs::file_size(p)) : read_text(p);
    };
    std::vector<std::string> contents;
    for (const auto& n : before) contents.push_back(content(n));
    Spawn s{dir_, args};
    if (spawn) s = *spawn, s.dir = dir_, s.args = args;
    const Exit e = run_skin(s);
    EXPECT_EQ(e.code, 2) << e.err;
    EXPECT_TRUE(one_line(e.err)) << e.err;
    for (const auto& n : needles) EXPECT_NE(e.err.find(n), std::string::npos) << "'" << n << "' not in: " << e.err;
    EXPECT_EQ(listing(), before) << "files appeared or vanished";
    for (std::size_t i = 0; i < before.size(); ++i) EXPECT_EQ(content(before[i]), contents[i]) << before[i];
  }
};

// --- a full disk ---------------------------------------------------------------------------

// /dev/full: a device written in place; the failure is reported once, naming it.
TEST_F(Faults, DevFullFailsWithOneLine) {
  expect_one_line_failure("spectrum --preset tanned --format json -o /dev/full", {"/dev/full", "No space left"});
  expect_one_line_failure("color --preset tanned --format csv -o /dev/full", {"/dev/full", "No space left"});
}

// A file-size limit (RLIMIT_FSIZE, SIGXFSZ ignored) makes every write past it fail as on a full
// disk, for text and for the libraries that write images (libpng, OpenEXR, Cairo): one line, no
// temporary file, the existing output untouched.
TEST_F(Faults, WriteBeyondTheSpaceLeftLosesNothing) {
  for (const char* name : {"out.json", "out.png", "out.exr", "plot.png", "params.exr", "fit.csv"})
    write_text(dir_ / name, kPrevious);
  skin::image::Image tex(16, 16);
  for (std::size_t i = 0; i < tex.rgb.size(); ++i) tex.rgb[i] = 0.2f + 0.5f * static_cast<float>(i % 7) / 7.0f;
  skin::image::write_image((dir_ / "tex.png").string(), tex);
  Spawn limit;
  limit.file_size_limit = 512;  // bytes: smaller than every output below
  expect_one_line_failure("spectrum --preset tanned -o out.json", {"out.json", "File too large"}, &limit);
  expect_one_line_failure("render --resolution 48x32 --spp 1 -o out.png", {"out.png"}, &limit);
  expect_one_line_failure("render --resolution 48x32 --spp 1 -o out.exr", {"out.exr"}, &limit);
  expect_one_line_failure("spectrum --preset tanned --format json --plot plot.png", {"plot.png"}, &limit);
  expect_one_line_failure("fit --texture tex.png --solver multipole -o params.exr", {"params.exr"}, &limit);
}

// A real full file system where the test may mount one (root in a container that allows it):
// a 64 KiB tmpfs, filled up.
class FullTmpfs : public Faults {
 protected:
  void SetUp() override {
    Faults::SetUp();
    mnt_ = dir_ / "small";
    fs::create_directories(mnt_);
    if (::mount("tmpfs", mnt_.c_str(), "tmpfs", 0, "size=64k") != 0)
      GTEST_SKIP() << "cannot mount a tmpfs here: " << std::strerror(errno);
    mounted_ = true;
  }
  void TearDown() override {
    if (mounted_) ::umount(mnt_.c_str());
    Faults::TearDown();
  }
  fs::path mnt_;
  bool mounted_ = false;
};

TEST_F(FullTmpfs, FullFileSystemLosesNothing) {
  write_text(mnt_ / "out.json", kPrevious);
  write_text(mnt_ / "out.png", kPrevious);
  {  // fill what is left
    std::FILE* f = std::fopen((mnt_ / "filler").c_str(), "wb");
    ASSERT_NE(f, nullptr);
    const std::string block(4096, 'x');
    while (std::fwrite(block.data(), 1, block.size(), f) == block.size()) {
    }
    std::fclose(f);
  }
  expect_one_line_failure("spectrum --preset tanned -o small/out.json", {"small/out.json", "No space left"});
  expect_one_line_failure("render --resolution 48x32 --spp 1 -o small/out.png", {"small/out.png"});
}

// --- inputs that are missing, unreadable, truncated or of the wrong type -------------------

struct BadInput {
  std::string file;     // written into the test directory
  std::string content;  // its bytes ("<dir>": a directory)
  std::string args;     // the command reading it
};

TEST_F(Faults, BadInputFilesNameTheFileInOneLine) {
  const std::string png = read_text(kFuzzAssets + "/skin8.png");
  const std::string jpg = read_text(kFuzzAssets + "/skin8.jpg");
  const std::string glb = read_text(kFuzzAssets + "/quad.glb");
  const std::string gltf = read_text(kFuzzAssets + "/quad.gltf");
  // An EXR made by the project (tiny), to truncate.
  skin::image::Image img(8, 8);
  skin::image::write_image((dir_ / "whole.exr").string(), img);
  const std::string exr = read_text(dir_ / "whole.exr");
  fs::remove(dir_ / "whole.exr");
  const std::string scene_with = R"({"camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0]}, "objects": [)";
  const std::vector<BadInput> cases = {
      // measured spectra (CSV)
      {"s.csv", "wavelength_nm,R\n450,0.3\n500", "fit --spectrum s.csv"},        // truncated row
      {"s.csv", png, "fit --spectrum s.csv"},                                    // an image
      {"s.csv", "", "fit --spectrum s.csv"},                                     // empty
      {"s.csv", "<dir>", "fit --spectrum s.csv"},                                // a directory
      {"absent.csv", "<none>", "fit --spectrum absent.csv"},                     // missing
      // parameter files (JSON)
      {"p.json", R"({"melanin": 0.)", "spectrum --params p.json"},               // truncated
      {"p.json", png, "spectrum --params p.json"},                               // an image
      {"p.json", "[1, 2]", "spectrum --params p.json"},                          // wrong JSON type
      {"p.json", "<dir>", "spectrum --params p.json"},
      // scenes (JSON)
      {"s.json", R"({"camera": {"eye": [0, 0)", "render s.json -o out.png"},
      {"s.json", jpg, "render s.json -o out.png"},
      {"s.json", "<dir>", "render s.json -o out.png"},
      // meshes
      {"m.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n", "figure 8 --mesh m.obj -o out.png"},  // vertex 3 missing
      {"m.obj", png, "figure 8 --mesh m.obj -o out.png"},
      {"m.glb", glb.substr(0, glb.size() / 2), "figure 8 --mesh m.glb -o out.png"},
      {"m.gltf", gltf.substr(0, gltf.size() / 2), "figure 8 --mesh m.gltf -o out.png"},
      {"m.glb", png, "figure 8 --mesh m.glb -o out.png"},
      {"m.gltf", "<dir>", "figure 8 --mesh m.gltf -o out.png"},
      // textures
      {"t.png", png.substr(0, png.size() / 2), "fit --texture t.png -o p.exr"},
      {"t.jpg", jpg.substr(0, 100), "fit --texture t.jpg -o p.exr"},
      {"t.exr", exr.substr(0, exr.size() / 2), "fit --texture t.exr -o p.exr"},
      {"t.png", gltf, "fit --texture t.png -o p.exr"},
      {"t.exr", png, "fit --texture t.exr -o p.exr"},
      {"t.png", "<dir>", "fit --texture t.png -o p.exr"},
      // a scene's albedo texture and parameter map
      {"t.png", png.substr(0, 30),
       "render s.json -o out.png|" + scene_with +
           R"({"sphere": {"center": [0, 0, 0], "radius": 1}, "material": "m"}], "materials": {"m": {"type": "diffuse", "albedo_texture": "t.png"}}})"},
      {"m.exr", exr.substr(0, exr.size() - 20),
       "render s.json -o out.png|" + scene_with +
           R"({"sphere": {"center": [0, 0, 0], "radius": 1}, "material": "m"}], "materials": {"m": {"type": "skin", "parameter_maps": {"melanin": {"texture": "m.exr"}}}}})"},
  };
  for (const BadInput& c : cases) {
    std::string args = c.args;
    if (const auto bar = args.find('|'); bar != std::string::npos) {  // a scene to write first
      write_text(dir_ / "s.json", args.substr(bar + 1));
      args = args.substr(0, bar);
    }
    if (c.content == "<dir>") fs::create_directories(dir_ / c.file);
    else if (c.content != "<none>") write_text(dir_ / c.file, c.content);
    expect_one_line_failure(args, {c.file});
    fs::remove_all(dir_ / c.file);
    fs::remove(dir_ / "s.json");
  }
}

// A file the user cannot read (as root every file is readable: skipped then).
TEST_F(Faults, UnreadableFileNamesTheFile) {
  if (::geteuid() == 0) GTEST_SKIP() << "root reads every file";
  write_text(dir_ / "p.json", R"({"melanin": 0.02})");
  fs::permissions(dir_ / "p.json", fs::perms::none);
  expect_one_line_failure("spectrum --params p.json", {"p.json", "Permission denied"});
  fs::permissions(dir_ / "p.json", fs::perms::owner_all);
}

// --- requests too large to run ---------------------------------------------------------------

// A 2 GiB CSV (sparse: no disk used) is refused before it is read.
TEST_F(Faults, HugeCsvIsRefusedBeforeReading) {
  {
    std::FILE* f = std::fopen((dir_ / "huge.csv").c_str(), "wb");
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(::ftruncate(::fileno(f), 2LL << 30), 0);
    std::fclose(f);
  }
  const auto t0 = std::chrono::steady_clock::now();
  expect_one_line_failure("fit --spectrum huge.csv", {"huge.csv", "2048 MiB", "256 MiB"});
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
}

// Counts beyond what any run needs are refused by their option.
TEST_F(Faults, ImpossibleCountsAreRefused) {
  expect_one_line_failure("profile --samples 1000000000", {"--samples", "1000000000"});
  expect_one_line_failure("mc --preset pale --wavelength 650 --bins 100000000", {"bins"});
}

// Requests that would take weeks are refused with their estimate before work starts.
TEST_F(Faults, WeeksLongRequestsAreRefusedWithAnEstimate) {
  expect_one_line_failure("render --resolution 16384x16384 --spp 100000 --threads 2 -o big.png",
                          {"render of 16384x16384 pixels", "would take about", "refused"});
  expect_one_line_failure("mc --preset pale --wavelength 650 --photons 1000000000000 --threads 2 -o mc.json",
                          {"1000000000000 photons", "would take about", "refused"});
}

// Requests that would take hours are announced with an estimate before they start; Ctrl-C
// then stops them without output.
TEST_F(Faults, HoursLongRequestsAreAnnouncedWithAnEstimate) {
  struct Request {
    std::string args, output;
  };
  for (const Request& r : {Request{"render --resolution 4096x4096 --spp 2048 --threads 2 -o big.png", "big.png"},
                           Request{"mc --preset pale --wavelength 650 --photons 3000000000 --threads 2 -o mc.json", "mc.json"}}) {
    SCOPED_TRACE(r.args);
    Spawn s{dir_, r.args};
    s.send_signal = SIGINT;
    // Ctrl-C once the estimate is out: how long that takes (the render measures its speed on
    // the scene's materials first) depends on the machine and the sanitizers, not on the program.
    // So does the estimate: hours here, days on a loaded machine under the sanitizers (a
    // sanitizer run beside a build read "about 2 days" and, waiting for "hours", was never
    // stopped), so the signal follows the warning's last words.
    s.signal_when = "Ctrl-C stops it";
    s.delay = 1;
    const Exit e = run_skin(s);
    EXPECT_NE(e.err.find("skin: warning: a "), std::string::npos) << e.err;
    EXPECT_TRUE(e.err.find("hours on") != std::string::npos || e.err.find("days on") != std::string::npos) << e.err;
    EXPECT_EQ(e.code, 128 + SIGINT) << e.err;
    EXPECT_FALSE(fs::exists(dir_ / r.output));
    EXPECT_EQ(listing(), std::vector<std::string>{}) << "temporary files left";
  }
}

// The Monte Carlo's estimate is of the stack asked for: a 14 um slab in air runs ~800 times faster
// than skin, so 10^10 photons there (92 hours at skin's speed, ~4 CPU-minutes here) are not
// announced as hours; the run is then stopped with Ctrl-C, without output.
TEST_F(Faults, MonteCarloEstimatesAreOfTheStackAsked) {
  Spawn s{dir_, "mc --layer sigma_a=0.017,sigma_s_prime=1.97,eta=1.47,g=0.13,thickness=0.014 "
                "--photons 10000000000 --threads 1 -o mc.json"};
  s.send_signal = SIGINT;
  s.delay = 2;
  const Exit e = run_skin(s);
  EXPECT_EQ(e.err.find("would take about"), std::string::npos) << e.err;
  EXPECT_EQ(e.code, 128 + SIGINT) << e.err;
  EXPECT_FALSE(fs::exists(dir_ / "mc.json"));
}

}  // namespace
