// End-to-end tests of `skin mc` and `skin validate` through the binary: JSON keys and units,
// reproducibility across thread counts, user errors exit 2 and leave no output file.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "../temp_dir.hpp"
#include "skin/mc/tabulate.hpp"
#include "skin/transport/random_walk_table.hpp"
#include "skin_test_paths.hpp"

namespace {

struct CliRun {
  int status;
  std::string out;
};
CliRun run_skin(const std::string& args) {
  const std::string cmd = std::string(SKIN_BINARY) + " " + args + " 2>/dev/null";
  FILE* p = ::popen(cmd.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf{};
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
  const int st = ::pclose(p);
  return {WEXITSTATUS(st), out};
}

TEST(CliMc, JsonHasTheDocumentedKeysAndIsReproducibleAcrossThreads) {
  const std::string args =
      "mc --layer sigma_a=0.1,sigma_s_prime=1,thickness=2,eta=1.4 --layer sigma_a=0.3,sigma_s_prime=1.5 "
      "--photons 5000 --seed 3 --bins 20 --radius-max 4 --format json";
  const CliRun a = run_skin(args + " --threads 1");
  const CliRun b = run_skin(args + " --threads 2");
  ASSERT_EQ(a.status, 0);
  ASSERT_EQ(b.status, 0);
  const auto ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  for (const char* k : {"R_specular", "R_d", "R_d_se", "T_d", "T_d_se", "photons", "seconds"})
    EXPECT_TRUE(ja.contains(k)) << k;
  EXPECT_EQ(ja["photons"].get<int>(), 5000);
  EXPECT_NEAR(ja["R_specular"].get<double>(), std::pow(0.4 / 2.4, 2), 1e-15);
  EXPECT_EQ(ja["profile"]["r_mm"].size(), 20u);
  EXPECT_NEAR(ja["profile"]["r_mm"][0].get<double>(), 0.1, 1e-15);  // bin centre, dr = 0.2
  EXPECT_EQ(ja["profile"]["R"].size(), 20u);
  EXPECT_EQ(ja["profile"]["R_se"].size(), 20u);
  EXPECT_EQ(ja["layers"][0]["g"].get<double>(), 0.9);  // default g
  EXPECT_NEAR(ja["layers"][0]["sigma_s"].get<double>(), 10.0, 1e-12);
  EXPECT_EQ(ja["R_d"], jb["R_d"]);
  EXPECT_EQ(ja["profile"]["R"], jb["profile"]["R"]);
}

// Issue 29: a non-absorbing half-space ran for minutes (no photon ends but by escaping, and that
// takes a number of steps without a finite mean). Now every path is bounded: the 200 photons
// end in about a second and the weight stopped at the bound is reported as "lost".
TEST(CliMc, NonAbsorbingHalfSpaceEndsAndReportsTheLostWeight) {
  const auto t0 = std::chrono::steady_clock::now();
  const CliRun r = run_skin("mc --layer sigma_a=0,sigma_s_prime=1 --photons 200 --format json");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(r.status, 0);
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["R_d"].get<double>() + j["lost"].get<double>(), 1.0, 1e-12);
  EXPECT_LT(j["lost"].get<double>(), 0.05);
  EXPECT_LT(seconds, 30.0);
}

TEST(CliMc, PresetAtOneWavelength) {
  const CliRun a = run_skin("mc --preset pale --wavelength 650 --photons 2000 --format json");
  ASSERT_EQ(a.status, 0);
  const auto j = nlohmann::json::parse(a.out);
  EXPECT_EQ(j["layers"].size(), 2u);
  EXPECT_EQ(j["wavelength_nm"].get<double>(), 650.0);
  EXPECT_GT(j["R_d"].get<double>(), 0.3);
  EXPECT_NEAR(j["R_d_incident"].get<double>(),
              j["R_d"].get<double>() * (1 - j["R_specular"].get<double>()), 1e-12);
}

TEST(CliMc, UserErrorsExitTwoAndLeaveNoFile) {
  const auto out = std::filesystem::temp_directory_path() / "skin_mc_cli_test.json";
  std::filesystem::remove(out);
  EXPECT_EQ(run_skin("mc --layer sigma_a=-1,sigma_s_prime=1 -o " + out.string()).status, 2);
  EXPECT_EQ(run_skin("mc --layer sigma_a=0.1,sigma_s_prime=1,g=1 -o " + out.string()).status, 2);
  EXPECT_EQ(run_skin("mc --layer sigma_a=0.1,sigma_s_prime=1 --photons 0 -o " + out.string()).status, 2);
  EXPECT_EQ(run_skin("mc --layer sigma_a=0.1,sigma_s_prime=1 --bins 0 -o " + out.string()).status, 2);
  EXPECT_EQ(run_skin("mc --layer sigma_a=0.1,sigma_s_prime=1 --wavelength 500").status, 2);
  EXPECT_EQ(run_skin("mc --layer sigma_a=0.1,sigma_s_prime=1 --melanin 0.1").status, 2);
  EXPECT_EQ(run_skin("mc --preset nosuch --wavelength 500").status, 2);
  EXPECT_EQ(run_skin("mc").status, 2);
  EXPECT_FALSE(std::filesystem::exists(out));
  // A file the user had is left as it was.
  { std::ofstream(out) << "keep"; }
  EXPECT_EQ(run_skin("mc --layer sigma_a=0.1,sigma_s_prime=0 -o " + out.string()).status, 2);
  std::ifstream in(out);
  std::string s;
  in >> s;
  EXPECT_EQ(s, "keep");
  std::filesystem::remove(out);
}

TEST(CliValidate, RejectsBadInputBeforeWork) {
  EXPECT_EQ(run_skin("validate").status, 2);  // --out is required
  const skin::test::TempDir tmp("skin_validate_cli");
  const auto dir = tmp.path() / "out";
  EXPECT_EQ(run_skin("validate --out " + dir.string() + " --photons 0").status, 2);
  EXPECT_EQ(run_skin("validate --out " + dir.string() + " --wavelength 5").status, 2);
  EXPECT_FALSE(std::filesystem::exists(dir / "README.md"));
}

TEST(CliTabulate, SmallTableParsesBackAndBadInputLeavesNoFile) {
  const auto out = std::filesystem::temp_directory_path() / "skin_tabulate_cli_test.csv";
  std::filesystem::remove(out);
  EXPECT_EQ(run_skin("tabulate-random-walk").status, 2);  // -o is required
  EXPECT_EQ(run_skin("tabulate-random-walk --photons 0 -o " + out.string()).status, 2);
  EXPECT_EQ(run_skin("tabulate-random-walk --photons -5 -o " + out.string()).status, 2);
  EXPECT_FALSE(std::filesystem::exists(out));
  // Few photons per node: a table the library reads back, each node's exits a distribution.
  const auto r = run_skin("tabulate-random-walk --photons 2000 --seed 3 -o " + out.string());
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("wrote "), std::string::npos) << r.out;
  std::ifstream in(out);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto t = skin::transport::RandomWalkTable::from_csv(text, out.string());
  ASSERT_EQ(t.alpha.size(), skin::mc::RandomWalkOptions::defaults().alpha.size());
  for (std::size_t i = 0; i < t.alpha.size(); ++i) {
    EXPECT_GT(t.R_d[i], 0) << t.alpha[i];
    EXPECT_LT(t.R_d[i], 1) << t.alpha[i];
  }
  std::filesystem::remove(out);
}

// The cross terms rebased onto other offsets: only with --cross --reuse, a file that is not
// offsets is refused without output, and the built-in terms rebased from the offsets they were
// computed against onto the same offsets are the built-in terms (to the file's 3 decimals).
TEST(CliTabulate, CrossTermsRebasedOntoTheSameOffsetsAreUnchanged) {
  const skin::test::TempDir tmp("skin_rebase_cli");
  const std::string out = (tmp.path() / "cross.csv").string(), data = std::string(SKIN_SOURCE_DIR) + "/data/";
  const std::string reuse = " --reuse " + data + "skin_stack_cross.csv";
  EXPECT_EQ(run_skin("tabulate-skin-profiles --rebase-from " + data + "skin_stack_offsets.csv -o " + out).status, 2);
  EXPECT_EQ(run_skin("tabulate-skin-profiles --cross" + reuse + " --rebase-from " + data + "d65.csv -o " + out).status, 2);
  EXPECT_FALSE(std::filesystem::exists(out));
  const auto r = run_skin("tabulate-skin-profiles --cross" + reuse + " --rebase-from " + data + "skin_stack_offsets.csv -o " + out);
  ASSERT_EQ(r.status, 0) << r.out;
  auto rows = [](const std::string& path) {
    std::ifstream in(path);
    std::vector<std::string> v;
    for (std::string line; std::getline(in, line);)
      if (!line.starts_with("#")) v.push_back(line);
    return v;
  };
  const auto a = rows(data + "skin_stack_cross.csv"), b = rows(out);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 1; i < a.size(); ++i) {  // (after the header) each value equal, -0.000 as 0.000
    std::istringstream sa(a[i]), sb(b[i]);
    for (std::string u, v; std::getline(sa, u, ',') && std::getline(sb, v, ',');)
      ASSERT_EQ(std::stod(u), std::stod(v)) << "row " << i;
  }
}

}  // namespace
