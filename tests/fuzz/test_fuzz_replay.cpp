// Replays the fuzz harnesses (fuzz/) on their seed corpora and on every input a fuzzer found
// (fuzz/regressions/<target>/): a harness aborts the process on a finding (a crash, a sanitizer
// report, an exception other than InputError, a broken invariant), so a finding that comes back
// fails this test. Adding a regression is adding its file.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#define SKIN_FUZZ_TARGETS(X)                                                               \
  X(layer) X(params_json) X(spectrum_csv) X(parameter_maps) X(scene_json) \
  X(mesh_obj) X(mesh_gltf) X(mesh_glb) X(texture_png) X(texture_jpg) X(texture_exr) X(batch_sets) \
  X(random_walk_table) X(skin_stack_table) X(python_convert)

#define SKIN_DECLARE(name) extern "C" int skin_fuzz_##name(const std::uint8_t* data, std::size_t size);
SKIN_FUZZ_TARGETS(SKIN_DECLARE)
#undef SKIN_DECLARE

namespace {

namespace fs = std::filesystem;
using Harness = int (*)(const std::uint8_t*, std::size_t);

struct Target {
  std::string name;
  Harness run;
};

std::vector<Target> targets() {
#define SKIN_ENTRY(name) {#name, skin_fuzz_##name},
  return {SKIN_FUZZ_TARGETS(SKIN_ENTRY)};
#undef SKIN_ENTRY
}

std::vector<fs::path> inputs(const std::string& dir) {
  std::vector<fs::path> files;
  if (fs::is_directory(dir))
    for (const auto& e : fs::directory_iterator(dir))
      if (e.is_regular_file()) files.push_back(e.path());
  return files;
}

std::string bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class FuzzReplay : public ::testing::TestWithParam<Target> {};

TEST_P(FuzzReplay, SeedsAndFoundInputsPass) {
  const Target& t = GetParam();
  const std::vector<fs::path> seeds = inputs(std::string(SKIN_FUZZ_DIR) + "/corpus/fuzz_" + t.name);
  const std::vector<fs::path> found = inputs(std::string(SKIN_FUZZ_DIR) + "/regressions/fuzz_" + t.name);
  EXPECT_FALSE(seeds.empty()) << "fuzz/corpus/fuzz_" << t.name << " has no seed";
  for (const auto* set : {&seeds, &found})
    for (const fs::path& p : *set) {
      SCOPED_TRACE(p.string());
      const std::string data = bytes(p);
      EXPECT_EQ(t.run(reinterpret_cast<const std::uint8_t*>(data.data()), data.size()), 0);
    }
}

INSTANTIATE_TEST_SUITE_P(Harnesses, FuzzReplay, ::testing::ValuesIn(targets()),
                         [](const auto& test) { return test.param.name; });

}  // namespace
