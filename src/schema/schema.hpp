#pragma once
// The schemas of the `skin` command's outputs: the JSON documents, the CSV columns and the table
// text of every command's result (spectrum, color, profile, parameters, presets, layers,
// illuminants here; fit, mc and batch in fit_schema.hpp, mc_schema.hpp, batch_schema.hpp), and
// the --params JSON the commands read. Built here once, without the command line, so that the
// `skin` executable (src/app), the WebAssembly module of the browser page (web/) and the Python
// package (python/, which converts the documents to dicts and numpy arrays) give the same keys and
// the same numbers. Pure data to text: no files are written here
// (ParameterFile::read reads one).
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "skin/color/color.hpp"
#include "skin/model/skin_model.hpp"
#include "skin/physics/layer.hpp"
#include "skin/physics/skin_parameters.hpp"
#include "skin/transport/model.hpp"
#include "skin/transport/profile.hpp"
#include "skin/transport/stack.hpp"

namespace skin::schema {

using json = nlohmann::ordered_json;  // NOLINT

// What a command computed, ready for each format: the JSON document, the columns of CSV (one
// header per column: the JSON key, with its unit in brackets when it has one, e.g.
// "sigma_a [1/mm]"; scalar results are columns too, repeated on every row, never comment lines
// that CSV readers drop), and for the table format the text a person reads (empty: the columns).
struct Column {
  std::string name;
  std::vector<double> numbers;    // a numeric column, or
  std::vector<std::string> text;  // a text column
  std::size_t rows() const { return numbers.empty() ? text.size() : numbers.size(); }
};
// A scalar result as a column of `rows` equal values.
Column constant_column(std::string name, double value, std::size_t rows);
struct Result {
  json document;
  std::vector<Column> columns;
  std::string table;
};
std::string to_csv(const std::vector<Column>& columns);  // csv_header + csv_rows
// The header line, and the rows alone (for output written in pieces: skin batch).
std::string csv_header(const std::vector<Column>& columns);
std::string csv_rows(const std::vector<Column>& columns);
// The table format of a result without table text: its columns, left-aligned.
std::string columns_table(const std::vector<Column>& columns);

// Fixed-width table for terminals: header row, then rows of numbers.
std::string format_table(const std::vector<std::string>& header,
                         const std::vector<std::vector<double>>& columns);
// Left-aligned text columns (first row: header), two spaces apart.
std::string format_text_table(const std::vector<std::vector<std::string>>& rows);
std::string format_csv(const std::vector<std::string>& header,
                       const std::vector<std::vector<double>>& columns);
// `v` with `digits` digits after the point ("%.*f"): the fixed-width numbers of tables.
std::string format_fixed(double v, int digits);
// Appends the columns `more` (of the same names, or `to` empty) to `to`, row after row.
void append_rows(std::vector<Column>& to, const std::vector<Column>& more);

json to_json(const physics::SkinParameters& p);
// A layer as the --layer keys name it: sigma_a, sigma_s_prime [1/mm], thickness_mm (null when
// semi-infinite), eta, g.
json to_json(const physics::Layer& l);
json to_json(const color::ColorSummary& c);
// {"totals": bool, "profile": bool, "reason": "..."} (reason only when one is false).
json to_json(const transport::Validity& v);
std::string color_table(const color::ColorSummary& c);
// The colour as CSV columns named like the JSON keys (XYZ.X, srgb_linear.r, srgb8.r, hex, lab.L).
std::vector<Column> color_columns(const color::ColorSummary& c);

// A parameter file: the JSON `skin fit` or `skin spectrum` writes (its "parameters" object), or
// a bare object of parameter keys (paper symbols accepted; null = not set; an optional "preset"
// naming the base set). read() and parse() throw InputError naming the file (`where`) and the key.
struct ParameterFile {
  std::string preset;  // empty: none
  std::vector<std::pair<const physics::ParameterInfo*, double>> values;
  static ParameterFile read(const std::string& path);
  // The same from a parsed document; `where` prefixes the messages ("params = 'FILE': ").
  static ParameterFile parse(const json& doc, const std::string& where);
  bool sets(const physics::ParameterInfo* info) const;
  void apply(physics::SkinParameters& p) const;  // the preset (if any), then the values
};

// The results of the commands, as `skin <command> --format json|csv|table` writes them.
// `preset` is the --preset the parameters started from.
Result spectrum_result(const model::SkinSpectrum& s, const std::string& preset);
// The colour `c` of s.R_d under c.illuminant (JSON key "illuminant"): skin::model::color_under(s, ...).
Result color_result(const model::SkinSpectrum& s, const std::string& preset, const color::ColorSummary& c);
// skin profile --rgb, and skin profile per wavelength.
Result rgb_profile_result(const transport::RgbProfile& rgb, const physics::SkinParameters& p, const std::string& preset,
                          const std::string& solver, const transport::Validity& validity);
Result spectral_profile_result(const transport::SpectralProfile& sp, const physics::SkinParameters& p,
                               const std::string& preset, const std::string& solver,
                               const transport::Validity& validity);
// Their JSON documents alone (the results' `document`), without the columns and the table text:
// for callers that need only the JSON (the web page's live update, Python's arrays of sets).
json spectrum_document(const model::SkinSpectrum& s, const std::string& preset);
json color_document(const model::SkinSpectrum& s, const std::string& preset, const color::ColorSummary& c);
json rgb_profile_document(const transport::RgbProfile& rgb, const physics::SkinParameters& p, const std::string& preset,
                          const std::string& solver, const transport::Validity& validity);
json spectral_profile_document(const transport::SpectralProfile& sp, const physics::SkinParameters& p,
                               const std::string& preset,
                               const std::string& solver, const transport::Validity& validity);
Result parameters_result();
Result presets_result();

// skin layers: the totals of `stack` by `solver` and its profile R [1/mm^2] at the radii r_mm (as
// asked: in their order, repeats kept; both empty when none are), each layer with the diffusion
// quantities of its slab in `diffusion` (alpha_prime, sigma_tr, z_r, z_b, A).
Result layers_result(const physics::LayerStack& stack, const transport::DiffusionStack& diffusion, const std::string& solver,
                     const transport::Totals& totals, const std::vector<double>& r_mm,
                     const std::vector<double>& R, const transport::Validity& validity);

// skin illuminants: every illuminant with its white point (x, y on CIE 015:2018's grid, 5 nm
// 380-780 nm) and its colour as a light in white-balanced linear sRGB.
Result illuminants_result();
// skin illuminants --compare: each preset's colour under each illuminant, spectral against RGB
// rendering (color::rgb_vs_spectral), computed by the caller.
struct IlluminantComparison {
  std::string solver;
  std::vector<std::string> illuminants;
  struct Row {
    std::string preset;
    std::vector<color::RgbVsSpectral> colors;  // one per illuminant, in their order
  };
  std::vector<Row> rows;
};
Result illuminant_comparison_result(const IlluminantComparison& comparison);

}  // namespace skin::schema
