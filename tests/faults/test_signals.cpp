// SIGINT and SIGTERM during the long commands (render, mc, validate, fit --texture,
// tabulate-top-layer, batch): the command stops within 2 s of the signal, exits with 128 + the signal's
// number after one line saying so, leaves no temporary file and every existing output as it was.
#include <random>

#include "process.hpp"
#include "skin/image/image.hpp"

namespace {
using namespace skin_test;

const std::string kPrevious = "previous output, must survive\n";

// A texture of distinct random colours, so that the texture fit has work for many seconds.
void write_noise_texture(const fs::path& path, int size) {
  skin::image::Image img(size, size);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.05f, 0.8f);
  for (float& v : img.rgb) v = u(rng);
  skin::image::write_image(path.string(), img);
}

struct Case {
  std::string name, args;
  std::vector<std::string> outputs;  // existing before the run; must keep their content
  int signal;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class Interrupted : public InDir, public ::testing::WithParamInterface<Case> {};

TEST_P(Interrupted, StopsPromptlyAndLosesNothing) {
  const Case& c = GetParam();
  if (c.args.find("noise.png") != std::string::npos) write_noise_texture(dir_ / "noise.png", 1024);
  for (const auto& o : c.outputs) {
    fs::create_directories((dir_ / o).parent_path());
    write_text(dir_ / o, kPrevious);
  }
  const std::vector<std::string> before = listing();
  Spawn s{dir_, c.args};
  s.send_signal = c.signal;
  s.delay = 1.5;
  const Exit e = run_skin(s);
  EXPECT_EQ(e.code, 128 + c.signal) << e.err;
  EXPECT_LT(e.seconds_after_signal, 2.0);
  const std::string line = std::string("skin: interrupted by ") + (c.signal == SIGINT ? "SIGINT" : "SIGTERM") +
                           ": stopped, no output written\n";
  EXPECT_TRUE(e.err.size() >= line.size() && e.err.compare(e.err.size() - line.size(), line.size(), line) == 0)
      << e.err;
  EXPECT_EQ(listing(), before) << "files appeared or vanished (temporary files?)";
  for (const auto& o : c.outputs) EXPECT_EQ(read_text(dir_ / o), kPrevious) << o;
}

INSTANTIATE_TEST_SUITE_P(
    LongCommands, Interrupted,
    ::testing::Values(
        Case{"render", "render --resolution 1024x1024 --spp 4096 -o out.png", {"out.png"}, SIGINT},
        Case{"render_term", "render --resolution 1024x1024 --spp 4096 --time-budget 600 -o out.exr", {"out.exr"}, SIGTERM},
        Case{"mc", "mc --preset pale --wavelength 650 --photons 100000000 -o out.json", {"out.json"}, SIGTERM},
        // Issue 29: in a non-absorbing half-space one photon can take seconds; it took 68 s to stop.
        Case{"mc_non_absorbing", "mc --layer sigma_a=0,sigma_s_prime=1 --photons 10000000 -o out.json", {"out.json"}, SIGINT},
        Case{"mc_non_absorbing_term", "mc --layer sigma_a=0,sigma_s_prime=1 --photons 10000000 -o out.json", {"out.json"}, SIGTERM},
        Case{"validate", "validate --out report --photons 100000000", {"report/README.md", "report/measured/README.md"}, SIGINT},
        Case{"fit_texture", "fit --texture noise.png -o params.exr", {"params.exr"}, SIGTERM},
        Case{"tabulate_random_walk", "tabulate-random-walk --photons 100000000 -o table.csv", {"table.csv"}, SIGINT},
        Case{"batch", "batch --sweep melanin=0:0.5:1000 --sweep hemoglobin=0.001:0.2:1000 --spectrum -o sets.csv",
             {"sets.csv"}, SIGTERM},
        Case{"batch_profile", "batch --sweep melanin=0:0.5:100000 --radius 0.1 --radius 1 -o sets.csv", {"sets.csv"}, SIGINT}),
    [](const auto& test) { return test.param.name; });

}  // namespace
