// skin::util's CSV reader and text-file reader at their edges: a byte-order mark, "nan" text, a
// file without its header line, a stream that never ends.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <iterator>
#include <filesystem>
#include <functional>
#include <fstream>

#include "skin/util/error.hpp"
#include "skin/util/input_file.hpp"
#include "skin/util/table.hpp"

namespace {
std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const skin::util::InputError& e) {
    return e.what();
  }
  return "(no error)";
}
}  // namespace

TEST(CsvReader, SkipsAUtf8ByteOrderMark) {
  const skin::util::Table t = skin::util::parse_csv("\xEF\xBB\xBFlambda_nm,R\n400,0.5\n", "s.csv");
  ASSERT_EQ(t.columns.size(), 2u);
  EXPECT_EQ(t.columns[0], "lambda_nm");
  EXPECT_EQ(t.column("lambda_nm"), 0u);
  // Also before comment lines.
  EXPECT_EQ(skin::util::parse_csv("\xEF\xBB\xBF# note\nmelanin\n0.1\n", "s.csv").columns[0], "melanin");
}

TEST(CsvReader, RefusesNanTextNamingLineAndColumnButTakesEmptyFields) {
  for (const char* nan : {"nan", "NaN", "-nan", "+NAN", "nan(1)"}) {
    EXPECT_EQ(message_of([&] { skin::util::parse_csv(std::string("lambda_nm,R\n400,0.5\n402,") + nan + "\n", "s.csv"); }),
              std::string("s.csv:3: column 'R' (field 2) is '") + nan +
                  "', not a number (leave the field empty for a missing value)");
  }
  const skin::util::Table t = skin::util::parse_csv("lambda_nm,R\n400,\n402,0.5\n", "s.csv");
  EXPECT_TRUE(std::isnan(t.data[1][0]));  // empty: a missing value
  EXPECT_EQ(skin::util::parse_csv("a,b\n1,inf\n", "s.csv").data[1][0], HUGE_VAL);  // data files hold inf
}

// Plain lines (numbers and commas only) take a fast path; any other line the general one. Both
// give the same numbers bit for bit: a table written plainly and the same one written with
// spaces, '+' signs and CR line ends (the general path) are equal; and what the fast path must
// leave to the general one still reads or fails as before (a wrong field count, junk after a
// number, an empty field, a trailing comma, "nan").
TEST(CsvReader, PlainLinesReadAsTheGeneralPathReadsThem) {
  std::string plain = "a,b,c\n", dressed = "a,b,c\n";
  const char* numbers[] = {"0", "-0", "1e-300", "4.9e-324", "1.7976931348623157e308", "0.1", "-2.5e+3", "inf", "-inf",
                           "123456789.123456789", "7E2", ".5", "5."};
  for (std::size_t i = 0; i < std::size(numbers); ++i) {
    const std::string x = numbers[i], y = numbers[(i + 5) % std::size(numbers)], z = numbers[(i + 9) % std::size(numbers)];
    plain += x + "," + y + "," + z + "\n";
    auto dress = [](const std::string& v) { return v[0] == '-' ? " " + v : "+" + v + " "; };
    dressed += dress(x) + ", " + dress(y) + "," + dress(z) + "\r\n";
  }
  const skin::util::Table p = skin::util::parse_csv(plain, "p.csv"), d = skin::util::parse_csv(dressed, "d.csv");
  ASSERT_EQ(p.rows(), std::size(numbers));
  for (std::size_t c = 0; c < 3; ++c)
    for (std::size_t r = 0; r < p.rows(); ++r)
      EXPECT_EQ(std::memcmp(&p.data[c][r], &d.data[c][r], sizeof(double)), 0) << c << " " << r;
  EXPECT_EQ(p.data[0][1], -0.0);
  EXPECT_TRUE(std::signbit(p.data[0][1]));
  EXPECT_EQ(message_of([] { skin::util::parse_csv("a,b\n1,2,3\n", "s.csv"); }),
            "s.csv:2: expected 2 comma-separated fields, found 3");
  EXPECT_EQ(message_of([] { skin::util::parse_csv("a,b\n1\n", "s.csv"); }), "s.csv:2: expected 2 comma-separated fields, found 1");
  EXPECT_EQ(message_of([] { skin::util::parse_csv("a,b\n1,2x\n", "s.csv"); }), "s.csv:2: field 2 ('2x') is not a number");
  EXPECT_EQ(message_of([] { skin::util::parse_csv("a,b\n1,1e\n", "s.csv"); }), "s.csv:2: field 2 ('1e') is not a number");
  EXPECT_EQ(message_of([] { skin::util::parse_csv("a,b\n1,nan\n", "s.csv"); }),
            "s.csv:2: column 'b' (field 2) is 'nan', not a number (leave the field empty for a missing value)");
  const skin::util::Table t = skin::util::parse_csv("a,b,c\n1,,3\n4,5,\n", "s.csv");
  EXPECT_TRUE(std::isnan(t.data[1][0]));
  EXPECT_TRUE(std::isnan(t.data[2][1]));
  EXPECT_EQ(t.data[0][1], 4.0);
}

TEST(CsvReader, RefusesAFirstLineOfNumbers) {
  EXPECT_EQ(message_of([] { skin::util::parse_csv("# spectrum\n400,0.5\n402,0.25\n", "s.csv"); }),
            "s.csv:2: the first line ('400,0.5') holds numbers, not column names: the file needs a header "
            "line naming its columns");
  EXPECT_EQ(message_of([] { skin::util::parse_csv("0.1\n0.2\n", "s.csv"); }).rfind("s.csv:1: the first line ('0.1')", 0), 0u);
  // One name among numbers is a header.
  EXPECT_EQ(skin::util::parse_csv("lambda_nm,400\n1,2\n", "s.csv").columns[1], "400");
}

TEST(TextFileReader, RefusesNulBytesAtOnce) {
  EXPECT_EQ(message_of([] { skin::util::io::read_file("/dev/zero", "params"); }),
            "params = '/dev/zero': not a text file (a NUL byte at byte 0)");
  const auto path = std::filesystem::temp_directory_path() / ("skin_nul_" + std::to_string(::getpid()) + ".json");
  std::ofstream(path, std::ios::binary) << std::string("{\"melanin\": 0.1}\n\0x", 18);
  EXPECT_EQ(message_of([&] { skin::util::io::read_file(path.string(), "params"); }),
            "params = '" + path.string() + "': not a text file (a NUL byte at byte 17)");
  std::filesystem::remove(path);
}

// A stream is read to at most max_bytes + 1 bytes, whatever its length: what it did not take
// stays in the pipe (the test holds a read end of its own to see it).
TEST(TextFileReader, ReadsAStreamToItsLimitPlusOneByte) {
  const auto fifo = std::filesystem::temp_directory_path() / ("skin_fifo_" + std::to_string(::getpid()));
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const int own_reader = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  const int writer = ::open(fifo.c_str(), O_WRONLY);
  ASSERT_GE(own_reader, 0);
  ASSERT_GE(writer, 0);
  const std::string offered(20000, 'y');  // within the pipe's buffer; the writer stays open
  ASSERT_EQ(::write(writer, offered.data(), offered.size()), static_cast<ssize_t>(offered.size()));
  EXPECT_EQ(message_of([&] { skin::util::io::read_file(fifo.string(), "CSV file", 10000); })
                .rfind("CSV file = '" + fifo.string() + "': more than the ", 0),
            0u);
  char rest[32768];
  const ssize_t left = ::read(own_reader, rest, sizeof rest);
  EXPECT_EQ(left, 20000 - 10001);
  ::close(writer);
  ::close(own_reader);
  std::filesystem::remove(fifo);
  // Exactly the limit is accepted.
  const auto file = std::filesystem::temp_directory_path() / ("skin_exact_" + std::to_string(::getpid()));
  std::ofstream(file, std::ios::binary) << std::string(100, 'a');
  EXPECT_EQ(skin::util::io::read_file(file.string(), "x", 100).size(), 100u);
  std::filesystem::remove(file);
}

// The reader reserves its columns from the text's size, not from what a header claims: 20 000
// columns over 200 000 empty lines (0.3 MB of text) once made it reserve 32 GB (20 000 columns x
// 200 000 lines of doubles) and fail with bad_alloc; what it reserves stays within 8 times the
// text's size, and the one data row is read.
TEST(CsvReader, ReservesNoMoreThanTheTextCanHold) {
  std::string text;
  for (int c = 0; c < 20000; ++c) text += (c ? ",c" : "c") + std::to_string(c);
  text += '\n' + std::string(200000, '\n');
  for (int c = 0; c < 20000; ++c) text += c ? ",1" : "1";
  text += '\n';
  const skin::util::Table t = skin::util::parse_csv(text, "wide.csv");
  ASSERT_EQ(t.rows(), 1u);
  std::size_t reserved = 0;
  for (const auto& column : t.data) reserved += column.capacity() * sizeof(double);
  EXPECT_LE(reserved, 8 * text.size());
}
