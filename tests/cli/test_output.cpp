// Output safety of -o (every command writes through skin::util::io): a regular file is replaced
// atomically, a symbolic link's target is written and the link stays a link, a FIFO or device
// is written in place and never replaced, "-" is standard output; a failing write (bad input,
// a full device) touches nothing that existed. The format follows -o's extension; a
// contradicting --format is refused.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <nlohmann/json.hpp>
#include <chrono>
#include <thread>

#include "cli_fixture.hpp"

namespace {
using json = nlohmann::json;
using skin_test::Cli;
using skin_test::CmdResult;
using skin_test::slurp;
namespace fs = std::filesystem;

TEST_F(Cli, OutputThroughSymlinkWritesTargetAndKeepsLink) {
  std::ofstream(dir_ / "real.json") << "precious";
  fs::create_symlink("real.json", dir_ / "link.json");
  // A failing command leaves the target as it was.
  EXPECT_EQ(run("color --melanin 2 -o link.json").code, 2);
  EXPECT_EQ(slurp(dir_ / "real.json"), "precious");
  // A succeeding one writes the target; the link is still a link to it.
  ASSERT_EQ(run("color -o link.json").code, 0);
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.json"));
  EXPECT_EQ(fs::read_symlink(dir_ / "link.json"), "real.json");
  EXPECT_TRUE(json::parse(slurp(dir_ / "real.json")).contains("color"));
  EXPECT_EQ(file_count(), 2u);  // no temporary file left
}

TEST_F(Cli, OutputToFifoIsWrittenInPlace) {
  const fs::path fifo = dir_ / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = slurp(fifo); });
  const CmdResult r = run("color --format csv -o fifo");
  reader.join();
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(received.find("XYZ.X,XYZ.Y,XYZ.Z"), 0u) << received;
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_EQ(file_count(), 1u);
}

TEST_F(Cli, OutputToDeviceIsWrittenInPlace) {
  ASSERT_EQ(run("spectrum --format csv -o /dev/null").code, 0);
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  // A full device fails with one line and exit 2.
  const CmdResult full = run("spectrum --format csv -o /dev/full");
  EXPECT_EQ(full.code, 2);
  EXPECT_NE(full.err.find("/dev/full: write failed"), std::string::npos) << full.err;
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
  EXPECT_EQ(file_count(), 0u);
}

TEST_F(Cli, DashIsStandardOutput) {
  const CmdResult r = run("color --format csv -o -");
  EXPECT_EQ(r.code, 0);
  EXPECT_EQ(r.out.find("XYZ.X,XYZ.Y,XYZ.Z"), 0u) << r.out;
  EXPECT_FALSE(fs::exists(dir_ / "-"));
}

TEST_F(Cli, RegularFileReplacedKeepsItsPermissions) {
  std::ofstream(dir_ / "out.csv") << "old";
  fs::permissions(dir_ / "out.csv", fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  ASSERT_EQ(run("color -o out.csv").code, 0);
  EXPECT_EQ(slurp(dir_ / "out.csv").find("XYZ.X,XYZ.Y,XYZ.Z"), 0u);  // csv from the extension
  EXPECT_EQ(fs::status(dir_ / "out.csv").permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
}

TEST_F(Cli, FormatFollowsExtensionAndContradictionIsRefused) {
  ASSERT_EQ(run("color -o c.json").code, 0);
  EXPECT_TRUE(json::parse(slurp(dir_ / "c.json")).contains("color"));
  ASSERT_EQ(run("color -o c.txt").code, 0);
  EXPECT_NE(slurp(dir_ / "c.txt").find("CIELAB"), std::string::npos);
  const CmdResult r = run("color --format csv -o c2.json");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--format csv contradicts the extension of -o 'c2.json'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "c2.json"));
}

}  // namespace

namespace {
// Counts refuse negative, fractional and zero-where-meaningless input (CLI11 alone wraps -1
// around in an unsigned option: --photons -1 once ran 2^64 - 1 photons).
struct BadCount {
  const char* args;
  const char* message;
};
class CliBadCount : public skin_test::Cli, public ::testing::WithParamInterface<BadCount> {};
TEST_P(CliBadCount, OneLineExitTwo) {
  const skin_test::CmdResult r = run(GetParam().args);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(GetParam().message), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(file_count(), 0u);
}
INSTANTIATE_TEST_SUITE_P(
    Cases, CliBadCount,
    ::testing::Values(
        BadCount{"mc --photons -1 --layer sigma_a=1,sigma_s_prime=1",
                 "--photons: -1 is out of range: must be a whole number >= 1"},
        BadCount{"mc --photons -1000 --layer sigma_a=1,sigma_s_prime=1", "--photons: -1000 is out of range"},
        BadCount{"mc --photons 1.5 --layer sigma_a=1,sigma_s_prime=1", "--photons: 1.5 is out of range"},
        BadCount{"mc --bins 0 --layer sigma_a=1,sigma_s_prime=1", "--bins: 0 is out of range"},
        BadCount{"mc --seed -3 --layer sigma_a=1,sigma_s_prime=1", "--seed: -3 is out of range"},
        BadCount{"mc --threads -2 --layer sigma_a=1,sigma_s_prime=1", "--threads: -2 is out of range"},
        BadCount{"profile --samples -5", "--samples: -5 is out of range: must be a whole number in [2, 1000000]"},
        BadCount{"render --spp 0 -o x.png", "--spp: 0 is out of range"},
        BadCount{"render --spp -4 -o x.png", "--spp: -4 is out of range"},
        BadCount{"render --max-depth -1 -o x.png", "--max-depth: -1 is out of range"},
        BadCount{"figure 9 -o x.png", "9 is out of range: must be one of 3, 4, 5, 6, 7, 8, 10, tones"},
        BadCount{"tabulate-random-walk --photons -1 -o t.csv", "--photons: -1 is out of range"},
        BadCount{"tabulate-skin-profiles --cross --cross-pairs g:x -o t.csv",
                 "--cross-pairs: 'g:x' is not one of g:eta, g:dermis_ratio, eta:dermis_ratio"},
        BadCount{"tabulate-skin-profiles --offsets --cross-pairs g:eta -o t.csv", "--cross-pairs is for --cross"},
        BadCount{"tabulate-skin-profiles --half-spaces --offset-nodes g=0.8 -o t.csv",
                 "--half-spaces takes only --output and --reuse"},
        BadCount{"tabulate-skin-profiles --half-spaces --offsets -o t.csv", "--offsets excludes --half-spaces"},
        BadCount{"tabulate-color-table --model x -o t.csv", "model = 'x' is unknown: choose paper or extended"}));
}  // namespace

namespace {
using skin_test::Cli;
using skin_test::CmdResult;
namespace fs = std::filesystem;

// Every command's output to a full standard output (/dev/full): exit 2 with one line, never a
// silent success (issue 29, item 4). Help and version text go through the same final check.
TEST_F(Cli, FullStandardOutputIsOneLineExitTwo) {
  const char* commands[] = {
      "spectrum",
      "color",
      "profile --samples 20",
      "layers --layer sigma_a=1,sigma_s_prime=10",
      "mc --layer sigma_a=1,sigma_s_prime=10 --photons 2000 --bins 10",
      "fit --srgb 169,143,116",
      "presets",
      "parameters",
      "illuminants",
      "illuminants --format csv",
      "batch --sweep melanin=0:0.1:2",
      "color --format json -o -",
      "--help",
      "color --help",
      "--version",
  };
  for (const char* args : commands) {
    const CmdResult r = run(args, "/dev/full");
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_EQ(r.err, "skin: error: output = '-': write failed: No space left on device\n") << args;
  }
}

// -o with an extension that names no format (or none) is refused before any work, with the
// allowed ones; --format makes any name acceptable; a device takes the default (issue 29, item 9).
TEST_F(Cli, OutputExtensionThatNamesNoFormatIsRefused) {
  const struct {
    std::string args, message;
  } cases[] = {
      {"color -o x.xml", "skin: error: --output: 'x.xml' has the extension .xml, which names no format: use "
                         ".json, .csv or .txt, or give --format"},
      {"spectrum -o noext", "skin: error: --output: 'noext' has no extension, which names no format: use "
                            ".json, .csv or .txt, or give --format"},
      {"parameters -o p.YAML", "skin: error: --output: 'p.YAML' has the extension .yaml, which names no "
                               "format: use .json, .csv or .txt, or give --format"},
      {"mc --layer sigma_a=1,sigma_s_prime=10 -o x.xml", "skin: error: --output: 'x.xml' has the extension"},
  };
  for (const auto& c : cases) {
    const CmdResult r = run(c.args);
    EXPECT_EQ(r.code, 2) << c.args;
    EXPECT_EQ(r.err.rfind(c.message, 0), 0u) << c.args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.args;
  }
  EXPECT_EQ(file_count(), 0u);
  ASSERT_EQ(run("color -o noext --format csv").code, 0);
  EXPECT_EQ(slurp(dir_ / "noext").find("XYZ.X,XYZ.Y,XYZ.Z"), 0u);
  ASSERT_EQ(run("color -o x.xml --format json").code, 0);
  EXPECT_TRUE(json::parse(slurp(dir_ / "x.xml")).contains("color"));
  EXPECT_EQ(run("presets -o /dev/null").code, 0);
}

// An empty value (an unset shell variable) is refused for every option that takes one, naming
// the option; it once read as 0 (issue 29, item 5).
TEST_F(Cli, EmptyValueIsRefusedNamingTheOption) {
  const struct {
    std::string args, option;
  } cases[] = {
      {"color --melanin ''", "--melanin"},
      {"color --C_m ''", "--melanin"},
      {"spectrum --lambda-min ''", "--lambda-min"},
      {"layers --layer sigma_a=1,sigma_s_prime=10 --eta-above ''", "--eta-above"},
      {"batch --sweep melanin=0:0.1:2 --wavelength ''", "--wavelength"},
      {"mc --layer sigma_a=1,sigma_s_prime=10 --photons ''", "--photons"},
      {"color --format ''", "--format"},
      {"color -o ''", "--output"},
      {"spectrum --plot ''", "--plot"},
      {"color --preset ''", "--preset"},
      {"color --illuminant ''", "--illuminant"},
  };
  for (const auto& c : cases) {
    const CmdResult r = run(c.args);
    EXPECT_EQ(r.code, 2) << c.args;
    EXPECT_EQ(r.out, "") << c.args;
    EXPECT_EQ(r.err.rfind("skin: error: " + c.option + ": the value is empty", 0), 0u) << c.args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.args;
  }
  const CmdResult r = run("color --melanin=");  // (CLI11: no value at all)
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err.rfind("skin: error: --melanin: ", 0), 0u) << r.err;
}

// --params: a parameter named twice (key and symbol) is refused, as in a --sets table and in
// Python, instead of one value silently winning (issue 29, item 5); a file that is no text
// (/dev/zero) is refused at once, not after 256 MiB (item 9).
TEST_F(Cli, ParamsFileRefusesARepeatedParameterAndBinaryInput) {
  std::ofstream(dir_ / "p.json") << R"({"C_m": 0.1, "melanin": 0.2})";
  const CmdResult r = run("color --params p.json");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "skin: error: params = 'p.json': key 'melanin' repeats parameter melanin (given as 'C_m' "
                   "already)\n");
  std::ofstream(dir_ / "sets.csv") << "melanin,C_m\n0.1,0.2\n";
  const CmdResult b = run("batch --sets sets.csv");
  EXPECT_EQ(b.code, 2);
  EXPECT_EQ(b.err, "skin: error: sets.csv: column 'C_m' repeats parameter melanin (given as 'melanin' already)\n");
  const auto start = std::chrono::steady_clock::now();
  const CmdResult z = run("color --params /dev/zero");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
  EXPECT_EQ(z.code, 2);
  EXPECT_EQ(z.err, "skin: error: params = '/dev/zero': not a text file (a NUL byte at byte 0)\n");
}

// A measured spectrum's "nan" sample is refused naming its line (it was dropped silently, as an
// empty field is); a file without its header line is refused, not read with its first sample as
// the column names (issue 29, item 5).
TEST_F(Cli, SpectrumCsvRefusesNanSamplesAndAMissingHeader) {
  std::ofstream(dir_ / "s.csv") << "lambda_nm,R\n400,0.3\n410,nan\n420,0.35\n";
  const CmdResult r = run("fit --spectrum s.csv");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "skin: error: s.csv:3: column 'R' (field 2) is 'nan', not a number (leave the field empty for "
                   "a missing value)\n");
  std::ofstream(dir_ / "n.csv") << "400,0.3\n410,0.32\n";
  const CmdResult n = run("fit --spectrum n.csv");
  EXPECT_EQ(n.code, 2);
  EXPECT_EQ(n.err.rfind("skin: error: n.csv:1: the first line ('400,0.3') holds numbers, not column names", 0), 0u)
      << n.err;
}

}  // namespace
