// The same inputs and seed give bit-identical output files across runs and thread counts, for
// render, mc, fit --texture, batch and tabulate-top-layer (through the binary, as a user runs them).
// fit has no --threads: its thread count is set by the CPUs it may run on (taskset).
#include <random>
#include <thread>

#include "process.hpp"
#include "skin/image/image.hpp"

namespace {
using namespace skin_test;

class Reproducible : public InDir {
 protected:
  // Runs `args` (which writes `output`) once per prefix, and returns the output's bytes per run.
  std::vector<std::string> outputs(const std::string& args, const std::string& output,
                                   const std::vector<std::vector<std::string>>& prefixes) {
    std::vector<std::string> out;
    for (const auto& p : prefixes) {
      fs::remove(dir_ / output);
      Spawn s{dir_, args};
      s.prefix = p;
      const Exit e = run_skin(s);
      EXPECT_EQ(e.code, 0) << args << "\n" << e.err;
      out.push_back(read_text(dir_ / output));
      EXPECT_FALSE(out.back().empty()) << args;
    }
    return out;
  }
  void expect_identical(const std::string& args, const std::string& output) {
    // Thread counts 1, 2, 2 (the same count twice: across runs), 3.
    std::vector<std::string> o;
    for (const char* t : {"1", "2", "2", "3"})
      o.push_back(outputs(args + " --threads " + t, output, {{}})[0]);
    for (std::size_t i = 1; i < o.size(); ++i) EXPECT_TRUE(o[i] == o[0]) << args << ": run " << i << " differs";
  }
};

TEST_F(Reproducible, Render) {
  expect_identical("render --resolution 64x48 --spp 4 --seed 5 -o out.exr", "out.exr");
  expect_identical("render --resolution 64x48 --spp 2 --seed 5 -o out.png", "out.png");
}

TEST_F(Reproducible, MonteCarlo) {
  expect_identical("mc --preset pale --wavelength 650 --photons 10000 --seed 9 -o out.csv", "out.csv");
}

TEST_F(Reproducible, Batch) {
  // Two chunks of 256 sets (the unit of parallel work) with spectra, and a few sets with
  // profiles; a 10 nm grid keeps the sanitizer build's runs short.
  expect_identical("batch --sweep melanin=0:0.5:26 --sweep hemoglobin=0.001:0.2:10 --spectrum --lambda-step 10 -o out.csv",
                   "out.csv");
  expect_identical("batch --sweep melanin=0:0.5:6 --radius 0.05 --radius 0.5 --radius 2 --lambda-step 10 -o out.csv",
                   "out.csv");
}

TEST_F(Reproducible, TabulateRandomWalk) {
  expect_identical("tabulate-random-walk --photons 2000 --seed 4 -o t.csv", "t.csv");
}

TEST_F(Reproducible, FitTexture) {
  skin::image::Image img(24, 16);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.05f, 0.8f);
  for (float& v : img.rgb) v = u(rng);
  skin::image::write_image((dir_ / "tex.png").string(), img);
  std::vector<std::vector<std::string>> prefixes = {{}, {}};
  if (std::thread::hardware_concurrency() >= 2) prefixes.push_back({"taskset", "-c", "0"});
  // The multipole solver: the fit's parallel parts are the same with either, and it is fast.
  const auto o = outputs("fit --texture tex.png --solver multipole -o params.exr", "params.exr", prefixes);
  for (std::size_t i = 1; i < o.size(); ++i) EXPECT_TRUE(o[i] == o[0]) << "run " << i << " differs";
}

}  // namespace
