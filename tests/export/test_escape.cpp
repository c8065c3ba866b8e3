// Names and paths in generated files (skin/util/escape.hpp): each format's escaping function
// round-trips hostile text through the format's real parser (Python's ast, expat, Python's csv,
// nlohmann-json) or, where none is at hand, a reference parse of the format's rules (pbrt-v4's
// tokenizer, C#'s string literals); text a format cannot hold is refused with one line naming
// the parameter. Then every export target, given hostile file names, writes files that parse and
// hold the names exactly, and hostile --name values are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "../temp_dir.hpp"
#include "export_schema.hpp"
#include "skin/export/export.hpp"
#include "skin/util/error.hpp"
#include "skin/util/escape.hpp"
#include "skin_test_paths.hpp"

using namespace skin;
using skin::util::InputError;
using skin::physics::SkinParameters;
using skin::physics::find_preset;
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

// Text a user could give as a file name or a name: quotes of every kind, backslashes, line
// breaks, markup, the payload of issue 29, format-specific syntax, and non-ASCII text.
std::vector<std::string> hostile() {
  return {"plain",
          "q\"+__import__(\"os\").system(\"touch PWNED\")+\"q",
          "q'+__import__('os').system('touch PWNED')+'q",
          "\"\"\" ''' \\\" \\' \\",
          "back\\slash\\n\\x41\\u0041\\",
          "new\nline",
          "cr\rlf\r\n",
          "tab\there",
          "<>&'\"",
          "&amp; &#10; ]]> <!-- --> <![CDATA[x]]>",
          "#comment \"string\" [ 1 2 ] Shape \"sphere\"",
          "{} {{}} %s %d ${x} $x",
          "unicode \xc3\xa9 \xe6\xbc\xa2\xe5\xad\x97 \xf0\x9f\x98\x80",
          "separators \xe2\x80\xa8 \xe2\x80\xa9 \xc2\x85 end",
          " spaces ",
          ",comma,",
          std::string("nul\0byte", 8)};
}

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void write(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

// tests/export/parse_exports.py on the files (Python's parsers; nothing is executed): {file:
// result}.
json parse_with_python(const std::vector<fs::path>& files) {
  std::string cmd = "/usr/bin/python3 " SKIN_SOURCE_DIR "/tests/export/parse_exports.py";
  for (const fs::path& f : files) cmd += " '" + f.string() + "'";  // temp paths: no quotes
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(::popen(cmd.c_str(), "r"), ::pclose);
  if (!pipe) throw std::runtime_error("cannot run " + cmd);
  std::string out;
  char buf[4096];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, pipe.get())) > 0;) out.append(buf, n);
  return json::parse(out);
}

// pbrt-v4's tokenizer (src/pbrt/parser.cpp, Tokenizer::Next), as its rules read: a quoted string
// runs to the next unescaped '"', a raw line feed in it is an error, '\' escapes the next
// character, decoded as b f n r t \ ' " (others are errors); '#' starts a comment to the end of
// the line; '[' and ']' are tokens; other tokens end at a space, tab, line break, quote or
// bracket. Strings are returned decoded with a leading '"' to tell them from other tokens.
std::vector<std::string> pbrt_tokens(const std::string& text) {
  std::vector<std::string> tokens;
  std::size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (c == ' ' || c == '\n' || c == '\t' || c == '\r') {
      ++i;
    } else if (c == '"') {
      std::string s = "\"";
      for (++i;; ++i) {
        if (i >= text.size()) throw std::runtime_error("premature EOF");
        if (text[i] == '"') break;
        if (text[i] == '\n') throw std::runtime_error("unterminated string");
        if (text[i] == '\\') {
          if (++i >= text.size()) throw std::runtime_error("premature EOF");
          const std::string from = "bfnrt\\'\"", to = "\b\f\n\r\t\\'\"";
          const std::size_t k = from.find(text[i]);
          if (k == std::string::npos) throw std::runtime_error("unexpected escaped character");
          s += to[k];
        } else {
          s += text[i];
        }
      }
      ++i;
      tokens.push_back(s);
    } else if (c == '[' || c == ']') {
      tokens.emplace_back(1, c);
      ++i;
    } else if (c == '#') {
      while (i < text.size() && text[i] != '\n' && text[i] != '\r') ++i;
    } else {
      const std::size_t j = text.find_first_of(" \n\t\r\"[]", i);
      const std::size_t end = j == std::string::npos ? text.size() : j;
      tokens.push_back(text.substr(i, end - i));
      i = end;
    }
  }
  return tokens;
}

// A C# regular string literal (C# specification, "Regular string literals"), decoded: no raw
// '"', '\' or line terminator (CR, LF, U+0085, U+2028, U+2029) inside; simple escapes and \uXXXX
// (code points below U+0800, enough for the escapes csharp_string writes).
std::string csharp_decode(const std::string& lit) {
  if (lit.size() < 2 || lit.front() != '"' || lit.back() != '"') throw std::runtime_error("not quoted");
  const std::string body = lit.substr(1, lit.size() - 2);
  for (const char* t : {"\n", "\r", "\xc2\x85", "\xe2\x80\xa8", "\xe2\x80\xa9"})
    if (body.find(t) != std::string::npos) throw std::runtime_error("raw line terminator");
  std::string s;
  for (std::size_t i = 0; i < body.size(); ++i) {
    if (body[i] == '"') throw std::runtime_error("raw quote");
    if (body[i] != '\\') {
      s += body[i];
      continue;
    }
    const char e = body.at(++i);
    const std::string from = "'\"\\0abfnrtv", to = std::string("'\"\\\0\a\b\f\n\r\t\v", 11);
    if (const std::size_t k = from.find(e); k != std::string::npos) {
      s += to[k];
    } else if (e == 'u') {
      const unsigned v = static_cast<unsigned>(std::stoul(body.substr(i + 1, 4), nullptr, 16));
      i += 4;
      if (v < 0x80) {
        s += static_cast<char>(v);
      } else if (v < 0x800) {
        s += static_cast<char>(0xC0 | (v >> 6));
        s += static_cast<char>(0x80 | (v & 0x3F));
      } else {
        s += static_cast<char>(0xE0 | (v >> 12));
        s += static_cast<char>(0x80 | ((v >> 6) & 0x3F));
        s += static_cast<char>(0x80 | (v & 0x3F));
      }
    } else {
      throw std::runtime_error("unknown escape");
    }
  }
  return s;
}

// The message of the InputError `f` throws ("" if none).
template <typename F>
std::string refusal(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const std::vector<std::string> kInvalidUtf8 = {
    "\xff", "a\x80z", "\xc0\x80", "\xe0\x80\xaf", "\xed\xa0\x80", "\xf4\x90\x80\x80", "\xe2\x82",
    "\xc3"};

}  // namespace

TEST(Escape, PythonStringsRoundTripThroughAst) {
  test::TempDir dir("skin-escape-py");
  std::string lines;
  for (const std::string& s : hostile()) {
    const std::string lit = util::escape::python_string(s, "output");
    EXPECT_EQ(lit.find_first_of("\n\r"), std::string::npos) << lit;  // one line
    lines += lit + "\n";
  }
  write(dir.path() / "a.lit", lines);
  const json r = parse_with_python({dir.path() / "a.lit"}).begin().value();
  ASSERT_TRUE(r.contains("values")) << r.dump();
  ASSERT_EQ(r["values"].size(), hostile().size());
  for (std::size_t i = 0; i < hostile().size(); ++i) EXPECT_EQ(r["values"][i], hostile()[i]) << i;
  EXPECT_FALSE(fs::exists("PWNED"));
}

TEST(Escape, XmlAttributesRoundTripThroughExpat) {
  test::TempDir dir("skin-escape-xml");
  std::vector<std::string> held;
  std::string lines;
  for (const std::string& s : hostile()) {
    if (s.find('\0') != std::string::npos) continue;  // refused below
    held.push_back(s);
    const std::string v = util::escape::xml_attribute(s, "output");
    EXPECT_EQ(v.find_first_of("\n\r\"<"), std::string::npos) << v;
    lines += v + "\n";
  }
  write(dir.path() / "a.attr", lines);
  const json r = parse_with_python({dir.path() / "a.attr"}).begin().value();
  ASSERT_TRUE(r.contains("values")) << r.dump();
  ASSERT_EQ(r["values"].size(), held.size());
  for (std::size_t i = 0; i < held.size(); ++i) EXPECT_EQ(r["values"][i], held[i]) << i;
  // XML 1.0 has no character for these: refused with the parameter and the character named.
  for (const std::string& s : {std::string("a\x01z"), std::string("nul\0", 4), std::string("\x1f"),
                               std::string("\x0b"), std::string("\xef\xbf\xbe"),
                               std::string("\xef\xbf\xbf")}) {
    const std::string m = refusal([&] { util::escape::xml_attribute(s, "output"); });
    EXPECT_EQ(m.rfind("output = '", 0), 0u) << m;
    EXPECT_NE(m.find("cannot be written in an XML file"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  EXPECT_NE(refusal([] { util::escape::xml_attribute("a\x01z", "output"); }).find("U+0001"), std::string::npos);
}

TEST(Escape, MitsubaAttributesRefuseWhatMitsubaReadsOtherwise) {
  // Mitsuba 3 substitutes $parameters in every attribute and refuses a '$' left over; a leading
  // '_' is reserved for its own ids. Everything else is XML's.
  for (const char* s : {"$x", "a$", "${x}"})
    EXPECT_NE(refusal([&] { util::escape::mitsuba_attribute(s, "name"); }).find("name = '"), std::string::npos) << s;
  EXPECT_NE(refusal([] { util::escape::mitsuba_attribute("_x", "name"); }).find("leading '_'"), std::string::npos);
  EXPECT_EQ(util::escape::mitsuba_attribute("x_<&>\"'", "name"), util::escape::xml_attribute("x_<&>\"'", "name"));
  EXPECT_NE(refusal([] { util::escape::mitsuba_attribute("a\x02", "name"); }), "");
}

TEST(Escape, PbrtStringsAreOneTokenOfPbrtV4) {
  // pbrt-v4 strings hold every character through its escapes: each escaped name is exactly one
  // string token, whatever follows it (no parameter injected), and decodes to the name.
  for (const std::string& s : hostile()) {
    const std::string lit = util::escape::pbrt_string(s, "output");
    EXPECT_EQ(lit.find('\n'), std::string::npos) << lit;
    const std::vector<std::string> t = pbrt_tokens("\"spectrum sigma_a\" " + lit + " \"float g\" [ 0 ]\n");
    ASSERT_EQ(t.size(), 6u) << lit;
    EXPECT_EQ(t[1], "\"" + s) << lit;
    EXPECT_EQ(t[2], "\"float g");
  }
  // The reference tokenizer does see an unescaped name's injection (the test can fail).
  const std::vector<std::string> raw =
      pbrt_tokens("\"spectrum sigma_a\" \"x\" \"float g\" [ 9 ] \"y.spd\"");
  EXPECT_EQ(raw.size(), 7u);
}

TEST(Escape, CsharpStringsDecodeToTheText) {
  for (const std::string& s : hostile()) {
    const std::string lit = util::escape::csharp_string(s, "name");
    EXPECT_EQ(csharp_decode(lit), s) << lit;
  }
}

TEST(Escape, CsvFieldsRoundTripThroughPythonsCsv) {
  test::TempDir dir("skin-escape-csv");
  std::vector<std::string> held;
  std::string text;
  for (const std::string& s : hostile()) {
    if (s.find('\0') != std::string::npos) continue;  // Python's csv refuses NUL
    held.push_back(s);
    text += util::escape::csv_field(s) + "," + util::escape::csv_field("next") + "\n";
  }
  write(dir.path() / "a.csv", text);
  const json r = parse_with_python({dir.path() / "a.csv"}).begin().value();
  ASSERT_TRUE(r.contains("rows")) << r.dump();
  ASSERT_EQ(r["rows"].size(), held.size());
  for (std::size_t i = 0; i < held.size(); ++i) {
    ASSERT_EQ(r["rows"][i].size(), 2u) << i;
    EXPECT_EQ(r["rows"][i][0], held[i]) << i;
  }
}

TEST(Escape, TextThatIsNotUtf8IsRefusedByEveryFormat) {
  for (const char* s : {"\xc3\xa9", "\xf0\x9f\x98\x80", "\xf4\x8f\xbf\xbf", "\xe2\x80\xa8"})
    EXPECT_NO_THROW(util::escape::require_utf8(s, "output")) << s;
  for (const std::string& s : kInvalidUtf8) {
    for (const auto& f : {util::escape::python_string, util::escape::xml_attribute, util::escape::mitsuba_attribute,
                          util::escape::pbrt_string, util::escape::csharp_string}) {
      const std::string m = refusal([&] { f(s, "output"); });
      EXPECT_EQ(m.rfind("output = '", 0), 0u) << m;
      EXPECT_NE(m.find("is not UTF-8 text"), std::string::npos) << m;
    }
  }
}

TEST(Escape, JsonNamesRoundTripThroughNlohmann) {
  // The JSON documents are nlohmann-json's; the fit report holds the file names as given.
  const exporting::Export e =
      exporting::export_skin("realtime", SkinParameters{}, transport::find_model("multipole"), {});
  std::vector<std::string> files;
  for (const std::string& s : hostile()) files.push_back("dir/" + s + ".json");
  const json j = json::parse(schema::fit_report_document(e.report, SkinParameters{}, "multipole", files).dump());
  EXPECT_EQ(j["files"].get<std::vector<std::string>>(), files);
  for (const std::string& s : kInvalidUtf8) {
    const std::string m = refusal([&] {
      schema::fit_report_document(e.report, SkinParameters{}, "multipole", {s + ".json"});
    });
    EXPECT_EQ(m.rfind("output = '", 0), 0u) << m;
  }
}

TEST(Escape, EveryTargetHoldsHostileFileNames) {
  // Every target with every hostile file name (the -o stem, which the files use to refer to
  // each other) and its textures or .spd files: each file parses with its format's parser, and
  // each reference holds the name exactly. Text a format cannot hold is refused with one line.
  const transport::Model& model = transport::find_model("multipole");
  const SkinParameters p = find_preset("caucasian").parameters;
  const exporting::ParameterMapsInput maps{"maps.exr", 1, 1, {"melanin"}, {{float(p.melanin)}}};
  const auto ours = exporting::prepare(p, model);
  test::TempDir dir("skin-escape-targets");
  struct Written {
    std::string target, stem;
    fs::path path;
  };
  std::vector<Written> written;
  std::vector<fs::path> for_python;
  int n = 0;
  // The texture targets fit their texel anew for each export: they take all hostile text in
  // one stem (its pieces joined), the payload alone, and a NUL, which XML refuses.
  std::string joined;
  for (const std::string& s : hostile())
    if (s.find('\0') == std::string::npos) joined += s;
  const std::vector<std::string> texture_stems = {joined, hostile()[1], hostile().back()};
  for (const exporting::Target& t : exporting::targets()) {
    for (const std::string& stem : t.takes_textures ? texture_stems : hostile()) {
      SCOPED_TRACE(std::string(t.name) + " / " + json(stem).dump(-1, ' ', true));
      exporting::Options o;
      o.stem = stem;
      o.spectra_files = true;
      const bool xml = t.extension == ".mtlx" || t.extension == ".xml";
      if (xml && t.takes_textures && stem.find('\0') != std::string::npos) {
        const std::string m = refusal([&] { exporting::export_skin(t.name, p, model, o, &maps); });
        EXPECT_EQ(m.rfind("output = '", 0), 0u) << m;
        continue;
      }
      const exporting::Export e = t.takes_textures ? exporting::export_skin(t.name, p, model, o, &maps)
                                                   : exporting::export_prepared(t.name, *ours, o);
      for (const exporting::TextFile& f : e.files) {
        const std::string suffix = f.suffix.empty() ? std::string(t.extension) : f.suffix;
        const fs::path path = dir.path() / ("f" + std::to_string(n++) + suffix);
        write(path, f.content);
        written.push_back({std::string(t.name), stem, path});
        if (suffix == ".py" || suffix == ".mtlx" || suffix == ".xml") for_python.push_back(path);
      }
    }
  }
  const json parsed = parse_with_python(for_python);
  EXPECT_FALSE(fs::exists("PWNED"));
  EXPECT_FALSE(fs::exists(dir.path() / "PWNED"));
  int references = 0;
  for (const Written& w : written) {
    SCOPED_TRACE(w.target + " " + w.path.filename().string());
    const std::string ext = w.path.extension().string();
    const std::string text = read(w.path);
    if (ext == ".py" || ext == ".mtlx" || ext == ".xml") {
      const json& r = parsed.at(w.path.string());
      ASSERT_FALSE(r.contains("error")) << r.dump();
      if (ext == ".py") {
        EXPECT_EQ(r["strings"]["NAME"], "spectral_skin");
        if (w.target == "cycles") {
          EXPECT_EQ(r["strings"]["COLOR_MAP"], w.stem + ".subsurface_color.png");
          EXPECT_EQ(r["strings"]["RADIUS_MAP"], w.stem + ".subsurface_radius.exr");
          references += 2;
        }
      } else if (w.target != "mitsuba3") {
        std::vector<std::string> files;
        for (const auto& a : r["attributes"])
          if (a[0] == "input" && a[1] == "value" && a[2].get<std::string>().find(".subsurface_") != std::string::npos)
            files.push_back(a[2]);
        EXPECT_EQ(files, (std::vector<std::string>{w.stem + ".subsurface_color.png",
                                                    w.stem + ".subsurface_radius.exr"}));
        references += 2;
      }
    } else if (ext == ".json") {
      const json j = json::parse(text);  // throws (fails the test) if it does not parse
      EXPECT_EQ(j["name"], "spectral_skin");
    } else if (ext == ".gltf") {
      const json j = json::parse(text);
      EXPECT_EQ(j["materials"][0]["name"], "spectral_skin");
    } else if (ext == ".pbrt") {
      std::vector<std::string> t;
      ASSERT_NO_THROW(t = pbrt_tokens(text));
      std::vector<std::string> spd;
      for (std::size_t i = 0; i + 1 < t.size(); ++i)
        if (t[i] == "\"spectrum sigma_a" || t[i] == "\"spectrum sigma_s") {
          if (t[i + 1][0] == '"') spd.push_back(t[i + 1].substr(1));
        }
      if (w.path.string().find(".two-layer") == std::string::npos) {
        EXPECT_EQ(spd, (std::vector<std::string>{w.stem + ".sigma_a.spd", w.stem + ".sigma_s.spd"}));
        references += 2;
      }
      if (w.path.string().find(".two-layer") != std::string::npos) {
        for (const char* medium : {"spectral_skin_epidermis", "spectral_skin_dermis"})
          EXPECT_NE(std::find(t.begin(), t.end(), std::string("\"") + medium), t.end()) << medium;
      }
    } else if (ext == ".cs") {
      // Every string literal of the script decodes (a C# parse of its strings).
      std::size_t i = 0;
      while ((i = text.find('"', i)) != std::string::npos) {
        std::size_t j = i + 1;
        while (text.at(j) != '"') j += text[j] == '\\' ? 2 : 1;
        EXPECT_NO_THROW(csharp_decode(text.substr(i, j - i + 1)));
        i = j + 1;
      }
      EXPECT_NE(text.find("\"Assets/spectral_skin.asset\""), std::string::npos);
    }
  }
  // cycles, openpbr and standard-surface (textures: the two MaterialX targets refuse the NUL)
  // and pbrt-v4 (.spd files, every stem).
  EXPECT_EQ(references, 2 * (3 * 3 - 2) + 2 * static_cast<int>(hostile().size()));
}

TEST(Escape, HostileNamesAreRefusedWithOneLine) {
  // --name names classes (Unity), nodes (MaterialX) and ids (Mitsuba), which cannot be escaped:
  // hostile names are refused before anything is made, naming the option.
  const auto ours = exporting::prepare(SkinParameters{}, transport::find_model("multipole"));
  for (const std::string& name : hostile()) {
    if (name == "plain") continue;
    exporting::Options o;
    o.name = name;
    for (const exporting::Target& t : exporting::targets()) {
      const std::string m = refusal([&] { exporting::export_prepared(t.name, *ours, o); });
      EXPECT_EQ(m.rfind("name = '", 0), 0u) << t.name << ": " << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
  // A leading '_' is an identifier, but Mitsuba reserves it: refused for mitsuba3 alone.
  exporting::Options o;
  o.name = "_skin";
  EXPECT_NE(refusal([&] { exporting::export_prepared("mitsuba3", *ours, o); }).find("leading '_'"),
            std::string::npos);
  EXPECT_NO_THROW(exporting::export_prepared("pbrt-v4", *ours, o));
}

TEST(Escape, DefaultFileNamesCannotShadowAPythonModule) {
  // spectral_skin.py beside a script would be imported as the package spectral_skin; the
  // default stem NAME.TARGET has a dot, which no module name has.
  for (const exporting::Target& t : exporting::targets()) {
    const std::string stem = exporting::default_stem(t, "spectral_skin");
    EXPECT_EQ(stem, "spectral_skin." + std::string(t.name));
    EXPECT_NE(stem + std::string(t.extension), "spectral_skin.py");
  }
}
