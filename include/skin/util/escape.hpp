#pragma once
// Names and paths written into generated files, escaped for the file's format: one function per
// format, through which every name and path a writer puts into a file goes (the exports in
// src/export, the CSV tables of src/schema). JSON documents are written by nlohmann-json, which
// escapes their strings itself; require_utf8 is their check.
//
// Each function takes the text and `what`, the parameter it came from as the user gave it
// ("output", "name"). Text a format cannot hold is refused with an InputError naming the
// parameter, the value and the character, never written broken:
// - every format: text that is not valid UTF-8 (a file name of arbitrary bytes);
// - XML (MaterialX, Mitsuba): the control characters XML 1.0 has no character for (all below
//   U+0020 but tab, line feed and carriage return), U+FFFE and U+FFFF;
// - Mitsuba 3 also: '$' (Mitsuba replaces $parameters in every attribute and refuses a '$' left
//   over) and a leading '_' (reserved for Mitsuba's own ids);
// - pbrt-v4: nothing else (its strings escape quotes, backslashes and newlines).
#include <string>
#include <string_view>

namespace skin::util::escape {

// InputError "what = '...': is not UTF-8 text ..." unless `text` is valid UTF-8 (no overlong
// forms, no surrogates, at most U+10FFFF).
void require_utf8(std::string_view text, std::string_view what);

// A Python 3 string literal, quotes included: "..." with \\, \", \n, \r, \t and \xNN for the
// other control characters; other characters as UTF-8 (Python source is UTF-8).
std::string python_string(std::string_view text, std::string_view what);

// The value of an XML attribute (to be written between double quotes): &amp; &lt; &gt; &quot;
// &apos;, and tab, line feed and carriage return as character references (a parser would turn
// them into spaces otherwise).
std::string xml_attribute(std::string_view text, std::string_view what);

// An attribute of Mitsuba 3's XML that names something (an id, a reference): xml_attribute, and
// refused where Mitsuba would read it otherwise ('$', a leading '_').
std::string mitsuba_attribute(std::string_view text, std::string_view what);

// A pbrt-v4 string, quotes included: "..." with \\, \", \n, \r, \t, \b, \f (the escapes
// pbrt-v4's tokenizer decodes; a raw line feed would end its string in error).
std::string pbrt_string(std::string_view text, std::string_view what);

// A C# regular string literal, quotes included: "..." with \\, \", \n, \r, \t, \0 and \uXXXX
// for the other control characters and for U+2028, U+2029 (C# line terminators).
std::string csharp_string(std::string_view text, std::string_view what);

// A CSV field (RFC 4180): as it is, or in double quotes (inner quotes doubled) when it holds a
// comma, a quote, a line feed or a carriage return. CSV holds any bytes: nothing is refused.
std::string csv_field(std::string_view text);

}  // namespace skin::util::escape
