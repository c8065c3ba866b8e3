#pragma once
// What every target's files and report share (internal to skin::export): the number formatting,
// the names' escaping options, the fit report and the comment block that opens each text file.
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "target.hpp"

namespace skin::exporting::detail {

using json = nlohmann::ordered_json;

// The options names and paths come from, as messages name them: every name and path a writer
// puts into a file goes through the escaping function of the file's format (skin/util/escape.hpp)
// with one of these.
inline constexpr std::string_view kName = "name";
inline constexpr std::string_view kOutput = "output";
// A name or path for a JSON document (nlohmann-json escapes it when it writes the document):
// UTF-8 text, or an InputError naming `what`.
std::string json_text(const std::string& text, std::string_view what);

// Every number an export writes carries 6 significant digits (num), in text and JSON alike
// (rounded): well above float precision of the renderers, well below the noise of the last bits
// in which two builds (compilers, libm, vectorisation: the CLI's and the web page's) differ, so
// that the files are the same byte for byte wherever they are made. Errors that vanish when the
// target matches exactly (a colour difference, a relative error) are rounded to 1e-6 absolutely
// (rounded_error): their noise around zero has no significant digits.
std::string num(double v);
double rounded(double v);
double rounded_error(double v);
// The document with every floating-point number rounded().
json rounded(json j);
std::string triple(const util::Rgb& c, const char* sep = ", ");
std::vector<double> vec(const util::Rgb& c);

// The fit report of ctx.target: its model in one line, its colour and its profile (per channel,
// on ctx.ref.radii) against ours.
FitReport fit_report(const Context& ctx, std::string target_model, const util::Rgb& R_d_target,
                     const std::array<std::vector<double>, 3>& R_target);
// The comment lines every text file opens with (each line starting with `prefix`): the skin, the
// units, the target's model, the fit's error and the report's notes.
std::string header_lines(const char* prefix, const Export& e, const Context& ctx);
// The report's values as JSON: a number for a single value, an array otherwise.
json values_json(const FitReport& r);
// The opening keys of a target's own JSON document: format, name and colour space.
json document_head(const std::string& format, const Options& o);

}  // namespace skin::exporting::detail
