#include "skin/util/escape.hpp"

#include <cstdint>
#include <cstdio>
#include <vector>

#include "skin/util/error.hpp"

namespace skin::util::escape {

namespace {

// One code point of the text and the bytes that encode it.
struct CodePoint {
  char32_t value;
  std::string_view bytes;
};

std::string hex_byte(unsigned char c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "\\x%02x", c);
  return buf;
}

std::string code_point_name(char32_t c) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "U+%04X", static_cast<unsigned>(c));
  return buf;
}

// The value as a message shows it: bytes outside ASCII as \xNN (it may not be UTF-8), control
// characters escaped by InputError.
std::string shown(std::string_view text) {
  std::string s;
  for (char c : text) {
    const auto u = static_cast<unsigned char>(c);
    s += u >= 0x80 ? hex_byte(u) : std::string(1, c);
  }
  return s;
}

[[noreturn]] void refuse(std::string_view text, std::string_view what, const std::string& why) {
  throw InputError(std::string(what) + " = '" + shown(text) + "': " + why);
}

// The code points of `text`; InputError naming `what` unless it is valid UTF-8.
std::vector<CodePoint> decode(std::string_view text, std::string_view what) {
  std::vector<CodePoint> out;
  std::size_t i = 0;
  auto bad = [&](std::size_t at) {
    refuse(text, what,
           "is not UTF-8 text (byte " + hex_byte(static_cast<unsigned char>(text[at])).substr(1) +
               " at offset " + std::to_string(at) + "): the files written hold text only");
  };
  while (i < text.size()) {
    const auto b0 = static_cast<unsigned char>(text[i]);
    // Length, the lead byte's bits and the least code point of that length (shorter forms of
    // a code point are overlong).
    std::size_t n = 1;
    char32_t c = b0, min = 0;
    if (b0 >= 0x80) {
      if ((b0 & 0xE0) == 0xC0) n = 2, c = b0 & 0x1F, min = 0x80;
      else if ((b0 & 0xF0) == 0xE0) n = 3, c = b0 & 0x0F, min = 0x800;
      else if ((b0 & 0xF8) == 0xF0) n = 4, c = b0 & 0x07, min = 0x10000;
      else bad(i);
    }
    if (i + n > text.size()) bad(i);
    for (std::size_t k = 1; k < n; ++k) {
      const auto b = static_cast<unsigned char>(text[i + k]);
      if ((b & 0xC0) != 0x80) bad(i + k);
      c = (c << 6) | (b & 0x3F);
    }
    if (c < min || c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF)) bad(i);
    out.push_back({c, text.substr(i, n)});
    i += n;
  }
  return out;
}

}  // namespace

void require_utf8(std::string_view text, std::string_view what) { decode(text, what); }

std::string python_string(std::string_view text, std::string_view what) {
  std::string s = "\"";
  for (const CodePoint& cp : decode(text, what)) {
    switch (cp.value) {
      case '\\': s += "\\\\"; break;
      case '"': s += "\\\""; break;
      case '\n': s += "\\n"; break;
      case '\r': s += "\\r"; break;
      case '\t': s += "\\t"; break;
      default:
        if (cp.value < 0x20 || cp.value == 0x7F) s += hex_byte(static_cast<unsigned char>(cp.value));
        else s += cp.bytes;
    }
  }
  return s + "\"";
}

std::string xml_attribute(std::string_view text, std::string_view what) {
  std::string s;
  for (const CodePoint& cp : decode(text, what)) {
    switch (cp.value) {
      case '&': s += "&amp;"; break;
      case '<': s += "&lt;"; break;
      case '>': s += "&gt;"; break;
      case '"': s += "&quot;"; break;
      case '\'': s += "&apos;"; break;
      case '\t': s += "&#9;"; break;
      case '\n': s += "&#10;"; break;
      case '\r': s += "&#13;"; break;
      default:
        if (cp.value < 0x20 || cp.value == 0xFFFE || cp.value == 0xFFFF)
          refuse(text, what,
                 code_point_name(cp.value) +
                     " cannot be written in an XML file: XML 1.0 has no such character");
        s += cp.bytes;
    }
  }
  return s;
}

std::string mitsuba_attribute(std::string_view text, std::string_view what) {
  if (text.find('$') != std::string_view::npos)
    refuse(text, what,
           "'$' cannot be written in a Mitsuba 3 file: Mitsuba reads $NAME in an attribute as a "
           "parameter to substitute");
  if (!text.empty() && text[0] == '_')
    refuse(text, what,
           "a leading '_' cannot be written in a Mitsuba 3 id: Mitsuba reserves it for its own");
  return xml_attribute(text, what);
}

std::string pbrt_string(std::string_view text, std::string_view what) {
  std::string s = "\"";
  for (const CodePoint& cp : decode(text, what)) {
    switch (cp.value) {
      case '\\': s += "\\\\"; break;
      case '"': s += "\\\""; break;
      case '\n': s += "\\n"; break;
      case '\r': s += "\\r"; break;
      case '\t': s += "\\t"; break;
      case '\b': s += "\\b"; break;
      case '\f': s += "\\f"; break;
      default: s += cp.bytes;
    }
  }
  return s + "\"";
}

std::string csharp_string(std::string_view text, std::string_view what) {
  std::string s = "\"";
  for (const CodePoint& cp : decode(text, what)) {
    switch (cp.value) {
      case '\\': s += "\\\\"; break;
      case '"': s += "\\\""; break;
      case '\n': s += "\\n"; break;
      case '\r': s += "\\r"; break;
      case '\t': s += "\\t"; break;
      case '\0': s += "\\0"; break;
      default:
        if (cp.value < 0x20 || cp.value == 0x7F || cp.value == 0x85 || cp.value == 0x2028 ||
            cp.value == 0x2029) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(cp.value));
          s += buf;
        } else {
          s += cp.bytes;
        }
    }
  }
  return s + "\"";
}

std::string csv_field(std::string_view text) {
  if (text.find_first_of(",\"\n\r") == std::string_view::npos) return std::string(text);
  std::string q = "\"";
  for (char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

}  // namespace skin::util::escape
