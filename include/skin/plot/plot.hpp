#pragma once
// Simple line plots written as PNG or SVG (Cairo): spectra with a colour swatch, radial
// profiles on log axes, validation plots.
#include <array>
#include <optional>
#include <string>
#include <vector>

namespace skin::plot {

struct Series {
  std::string label;
  std::vector<double> x, y;
  std::array<double, 3> rgb{0.1, 0.1, 0.1};  // line colour, sRGB-encoded 0-1
  bool dashed = false;
  bool markers = false;  // draw points instead of a line
};

struct Swatch {
  std::array<double, 3> rgb;  // sRGB-encoded 0-1
  std::string label;          // e.g. "#d8a890"
};

struct Figure {
  std::string title, x_label, y_label;
  bool log_x = false, log_y = false;
  std::optional<double> y_min, y_max;  // axis limits (default: from the data)
  std::vector<Series> series;
  std::vector<Swatch> swatches;  // drawn in a column at the right
  int width = 900, height = 560;
};

// A labelled grid of colour swatches (rows x columns, e.g. skin presets under illuminants); a
// cell is split in two, left | right, when `right` is given, with a caption below it.
struct SwatchGrid {
  std::string title;
  std::vector<std::string> rows, columns;
  struct Cell {
    std::array<double, 3> left{};                // sRGB-encoded 0-1
    std::optional<std::array<double, 3>> right;  // sRGB-encoded 0-1
    std::string caption;
  };
  std::vector<Cell> cells;  // row-major
  std::string note;         // below the grid; '\n' separates lines
};

// Scalar maps side by side (e.g. the texture fit's parameter maps), each in false colour from
// dark blue (its `lo`) through teal and green to yellow (its `hi`) with a colour bar and its range;
// a map is shown at most `panel` pixels wide (box-averaged). Non-finite values are grey.
struct MapPanel {
  std::string title;
  int width = 0, height = 0;
  std::vector<float> values;  // row-major, row 0 at the top
  double lo = 0, hi = 1;
};
struct MapSheet {
  std::string title;
  std::vector<MapPanel> panels;
  int columns = 2, panel = 360;
  std::string note;  // below the maps
};

// Writes the figure to `path`, PNG or SVG chosen by the extension, atomically. Throws InputError
// for another extension or a write failure.
void save(const Figure& fig, const std::string& path);
void save(const SwatchGrid& grid, const std::string& path);
// PNG only (the maps are raster images). Throws InputError for another extension, panels of
// inconsistent size, or a write failure.
void save(const MapSheet& sheet, const std::string& path);
// The false-colour scale of MapSheet at t in [0, 1] (clamped): sRGB-encoded 0-1.
std::array<double, 3> map_colour(double t);

}  // namespace skin::plot
