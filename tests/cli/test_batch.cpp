// skin batch: one row per parameter set, equal to the single commands; slices that concatenate
// to the whole; input checked before the first row.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_fixture.hpp"

using skin_test::Cli;
using skin_test::CmdResult;

namespace {

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream in(line);
  for (std::string f; std::getline(in, f, ',');) out.push_back(f);
  return out;
}

// The fields of `row` under the header names `names` (looked up in `header`).
std::vector<std::string> pick(const std::vector<std::string>& header, const std::vector<std::string>& row,
                              const std::vector<std::string>& names) {
  std::vector<std::string> out;
  for (const auto& n : names) {
    const auto it = std::find(header.begin(), header.end(), n);
    EXPECT_NE(it, header.end()) << n;
    if (it != header.end()) out.push_back(row.at(static_cast<std::size_t>(it - header.begin())));
  }
  return out;
}

}  // namespace

TEST_F(Cli, BatchSweepEqualsOneColorCallPerSet) {
  const CmdResult batch = run("batch --sweep melanin=0:0.5:21");
  ASSERT_EQ(batch.code, 0) << batch.err;
  EXPECT_EQ(batch.err, "");
  const auto rows = lines(batch.out);
  ASSERT_EQ(rows.size(), 22u);  // header + 21 sets
  const auto header = fields(rows[0]);
  for (std::size_t i = 0; i < 21; ++i) {
    const auto row = fields(rows[i + 1]);
    ASSERT_EQ(row.size(), header.size());
    EXPECT_EQ(row[0], std::to_string(i));
    const std::string melanin = pick(header, row, {"melanin"})[0];
    const CmdResult one = run("color --melanin " + melanin + " --format csv");
    ASSERT_EQ(one.code, 0) << one.err;
    const auto one_rows = lines(one.out);
    ASSERT_EQ(one_rows.size(), 2u);
    const auto one_header = fields(one_rows[0]);
    // Every colour column of `skin color`, the same text (10 significant digits).
    EXPECT_EQ(pick(header, row, one_header), fields(one_rows[1])) << "melanin " << melanin;
  }
  EXPECT_EQ(pick(header, fields(rows[8]), {"melanin"})[0], "0.175");  // 0.5 * 7 / 20, as typed
}

TEST_F(Cli, BatchSlicesConcatenateToTheWhole) {
  const std::string args =
      "batch --sweep melanin=0.01:0.4:3 --sweep C_h=0.001:0.1:4 --wavelength 550 --radius 1 --radius 0.2 "
      "--solver multipole";
  const CmdResult whole = run(args + " --threads 2");
  ASSERT_EQ(whole.code, 0) << whole.err;
  ASSERT_EQ(lines(whole.out).size(), 13u);
  std::string joined;
  for (const char* slice : {"0:5", "5:5", "5:11", "11:100"}) {
    const CmdResult part = run(args + " --rows " + slice + " --threads 1");
    ASSERT_EQ(part.code, 0) << part.err;
    joined += part.out;
  }
  EXPECT_EQ(joined, whole.out);
  // The grid is row-major: the last sweep varies fastest.
  const auto header = fields(lines(whole.out)[0]);
  EXPECT_EQ(pick(header, fields(lines(whole.out)[2]), {"melanin", "hemoglobin"}),
            (std::vector<std::string>{"0.01", "0.034"}));
  EXPECT_EQ(pick(header, fields(lines(whole.out)[5]), {"melanin", "hemoglobin"}),
            (std::vector<std::string>{"0.205", "0.001"}));
  for (const char* name : {"R_d_550nm", "R_1mm.g [1/mm^2]", "R_0.2mm.b [1/mm^2]"})
    EXPECT_NE(std::find(header.begin(), header.end(), name), header.end()) << name;
}

TEST_F(Cli, BatchProfileColumnsEqualSkinProfile) {
  const CmdResult batch = run("batch --sweep melanin=0.02:0.02:1 --radius 0.5 --radius 0.1");
  ASSERT_EQ(batch.code, 0) << batch.err;
  const CmdResult profile = run("profile --melanin 0.02 --rgb --format csv --radius-min 0.1 --radius-max 0.5 --samples 2");
  ASSERT_EQ(profile.code, 0) << profile.err;
  const auto ph = fields(lines(profile.out)[0]);
  const auto p01 = fields(lines(profile.out)[1]), p05 = fields(lines(profile.out)[2]);
  const auto bh = fields(lines(batch.out)[0]), row = fields(lines(batch.out)[1]);
  EXPECT_EQ(pick(bh, row, {"R_0.1mm.r [1/mm^2]", "R_0.1mm.g [1/mm^2]", "R_0.1mm.b [1/mm^2]"}),
            pick(ph, p01, {"R.r [1/mm^2]", "R.g [1/mm^2]", "R.b [1/mm^2]"}));
  // The profile's channel totals are the colour's linear sRGB.
  EXPECT_EQ(pick(bh, row, {"R_0.5mm.r [1/mm^2]", "srgb_linear.g"}), pick(ph, p05, {"R.r [1/mm^2]", "R_d.g"}));
}

TEST_F(Cli, BatchReadsSetsFromCsv) {
  std::ofstream(dir_ / "sets.csv") << "C_m,hemoglobin\n0.1,0.02\n,0.05\n";
  const CmdResult batch = run("batch --sets sets.csv --preset african --spectrum --lambda-step 50");
  ASSERT_EQ(batch.code, 0) << batch.err;
  const auto rows = lines(batch.out);
  ASSERT_EQ(rows.size(), 3u);
  const auto header = fields(rows[0]);
  EXPECT_EQ(std::vector<std::string>(header.begin(), header.begin() + 3),
            (std::vector<std::string>{"set", "melanin", "hemoglobin"}));
  // The empty cell keeps the base (african: melanin 0.5).
  EXPECT_EQ(pick(header, fields(rows[2]), {"melanin"})[0], "0.5");
  const CmdResult one = run("color --preset african --hemoglobin 0.05 --lambda-step 50 --format csv");
  const auto one_header = fields(lines(one.out)[0]);
  EXPECT_EQ(pick(header, fields(rows[2]), one_header), fields(lines(one.out)[1]));
  const CmdResult spectrum = run("spectrum --preset african --melanin 0.1 --hemoglobin 0.02 --lambda-step 50 --format csv");
  const auto sh = fields(lines(spectrum.out)[0]);
  EXPECT_EQ(pick(header, fields(rows[1]), {"R_d_400nm"})[0], pick(sh, fields(lines(spectrum.out)[1]), {"R_d"})[0]);
  EXPECT_EQ(pick(header, fields(rows[1]), {"R_d_700nm"})[0], pick(sh, fields(lines(spectrum.out)[7]), {"R_d"})[0]);
}

TEST_F(Cli, BatchBadInputIsOneLineBeforeAnyRow) {
  std::ofstream(dir_ / "sets.csv") << "melanin\n0.1\n2\n";
  const struct {
    std::string args, message;
  } cases[] = {
      {"batch --sets sets.csv -o out.csv", "skin: error: sets.csv: set 1: melanin (C_m) = 2 is out of range: allowed range is [0, 1]\n"},
      {"batch --sets sets.csv --melanin 0.2", "skin: error: melanin is given by both --melanin and sets.csv\n"},
      {"batch --sweep melanin=0:1.5:3", "skin: error: melanin (C_m) = 1.5 is out of range: allowed range is [0, 1]\n"},
      {"batch --sweep melanin=0:1", "skin: error: sweep = 'melanin=0:1' must look like KEY=START:STOP:COUNT (e.g. melanin=0:0.5:21)\n"},
      {"batch --sweep melanin=0:1:2.5", "skin: error: sweep = 'melanin=0:1:2.5': COUNT = 2.5 is out of range: must be a whole number in [1, 1e9]\n"},
      {"batch --sweep melanine=0:1:2", "skin: error: parameter 'melanine' is unknown: known parameters are"},
      {"batch --sweep melanin=0:1:2 --rows 3:1", "skin: error: rows = '3:1': need FIRST <= END\n"},
      {"batch --sweep melanin=0:1:2 --wavelength 551", "skin: error: wavelength = 551 nm is not on the grid"},
      {"batch --sweep melanin=0:1:2 -o out.json", "skin: error: output = 'out.json': skin batch writes CSV (.csv or .txt)\n"},
      {"batch", "skin: error: batch: give the parameter sets with --sets FILE.csv or --sweep KEY=START:STOP:COUNT\n"},
  };
  for (const auto& c : cases) {
    const CmdResult r = run(c.args);
    EXPECT_EQ(r.code, 2) << c.args;
    EXPECT_EQ(r.out, "") << c.args;
    EXPECT_EQ(r.err.rfind(c.message, 0), 0u) << c.args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.args;
  }
  EXPECT_FALSE(std::filesystem::exists(dir_ / "out.csv"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "out.json"));
  // A file output is the same bytes as standard output.
  const CmdResult to_file = run("batch --sweep melanin=0:0.5:3 -o sets-out.csv");
  ASSERT_EQ(to_file.code, 0) << to_file.err;
  EXPECT_EQ(to_file.out, "");
  EXPECT_EQ(skin_test::slurp(dir_ / "sets-out.csv"), run("batch --sweep melanin=0:0.5:3").out);
}

// A cell "nan" in --sets is refused naming its line and column (it once took the base value,
// like an empty cell); a UTF-8 byte-order mark (spreadsheets write one) is not part of the first
// column's name; a table without its header line is refused, not read with its first set as the
// names (issue 29, items 5 and 9).
TEST_F(Cli, BatchSetsRefuseNanCellsAndHeaderlessTablesAndSkipAByteOrderMark) {
  for (const std::string nan : {"nan", "NaN", "-nan"}) {
    std::ofstream(dir_ / "sets.csv") << "melanin,hemoglobin\n0.1,0.02\n0.2," << nan << "\n";
    const CmdResult r = run("batch --sets sets.csv");
    EXPECT_EQ(r.code, 2) << nan;
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(r.err, "skin: error: sets.csv:3: column 'hemoglobin' (field 2) is '" + nan +
                         "', not a number (leave the field empty for a missing value)\n");
  }
  std::ofstream(dir_ / "bom.csv") << "\xEF\xBB\xBFmelanin\n0.1\n";
  std::ofstream(dir_ / "plain.csv") << "melanin\n0.1\n";
  const CmdResult bom = run("batch --sets bom.csv");
  ASSERT_EQ(bom.code, 0) << bom.err;
  EXPECT_EQ(bom.out, run("batch --sets plain.csv").out);
  std::ofstream(dir_ / "noheader.csv") << "0.1,0.02\n0.2,0.03\n";
  const CmdResult h = run("batch --sets noheader.csv");
  EXPECT_EQ(h.code, 2);
  EXPECT_EQ(h.err, "skin: error: noheader.csv:1: the first line ('0.1,0.02') holds numbers, not column names: "
                   "the file needs a header line naming its columns\n");
}
