#include "skin/plot/plot.hpp"

#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>

#include "skin/util/atomic_file.hpp"
#include "skin/util/error.hpp"

namespace skin::plot {

using skin::util::InputError;

namespace {

struct Axis {
  double lo, hi;
  bool log;
  double map(double v, double a, double b) const {  // data -> pixel in [a, b]
    const double t = log ? (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo))
                         : (v - lo) / (hi - lo);
    return a + t * (b - a);
  }
  std::vector<double> ticks() const {
    std::vector<double> t;
    if (log) {
      for (double e = std::floor(std::log10(lo)); e <= std::ceil(std::log10(hi)); e += 1.0) {
        const double v = std::pow(10.0, e);
        if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9)) t.push_back(v);
      }
      return t;
    }
    const double span = hi - lo;
    const double raw = span / 6.0;
    const double mag = std::pow(10.0, std::floor(std::log10(raw)));
    double step = mag;
    for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
      if (m * mag >= raw) { step = m * mag; break; }
    for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9 * span; v += step)
      t.push_back(std::abs(v) < 1e-12 * span ? 0.0 : v);
    return t;
  }
};

std::string tick_label(double v, bool log) {
  char buf[32];
  if (log) {
    const int e = static_cast<int>(std::lround(std::log10(v)));
    if (e >= -2 && e <= 3) std::snprintf(buf, sizeof buf, "%g", v);
    else std::snprintf(buf, sizeof buf, "1e%d", e);
  } else {
    std::snprintf(buf, sizeof buf, "%g", v);
  }
  return buf;
}

Axis make_axis(const Figure& f, bool is_x) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  const bool log = is_x ? f.log_x : f.log_y;
  for (const auto& s : f.series)
    for (double v : is_x ? s.x : s.y)
      if (std::isfinite(v) && (!log || v > 0)) { lo = std::min(lo, v); hi = std::max(hi, v); }
  if (!is_x && f.y_min) lo = *f.y_min;
  if (!is_x && f.y_max) hi = *f.y_max;
  if (!std::isfinite(lo) || !std::isfinite(hi)) { lo = log ? 1e-3 : 0.0; hi = 1.0; }
  if (log) {
    if (!is_x && !f.y_min) lo = std::max(lo, hi * 1e-8);  // keep 8 decades at most
    lo = std::pow(10.0, std::floor(std::log10(lo)));
    hi = std::pow(10.0, std::ceil(std::log10(hi)));
    if (hi <= lo) hi = lo * 10;
  } else {
    if (hi <= lo) { hi = lo + 1.0; }
    if (!is_x && !f.y_min && lo > 0 && lo < 0.5 * hi) lo = 0.0;
  }
  return {lo, hi, log};
}

void draw(cairo_t* cr, const Figure& f) {
  const double W = f.width, H = f.height;
  const double swatch_w = f.swatches.empty() ? 0.0 : 150.0;
  const double left = 80, right = W - 30 - swatch_w, top = 50, bottom = H - 60;
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);

  const Axis ax = make_axis(f, true), ay = make_axis(f, false);
  // Grid and ticks.
  cairo_set_font_size(cr, 12);
  cairo_set_line_width(cr, 1.0);
  for (double t : ax.ticks()) {
    const double x = ax.map(t, left, right);
    cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
    cairo_move_to(cr, x, top); cairo_line_to(cr, x, bottom); cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    const std::string s = tick_label(t, ax.log);
    cairo_text_extents_t e; cairo_text_extents(cr, s.c_str(), &e);
    cairo_move_to(cr, x - e.width / 2, bottom + 18); cairo_show_text(cr, s.c_str());
  }
  for (double t : ay.ticks()) {
    const double y = ay.map(t, bottom, top);
    cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
    cairo_move_to(cr, left, y); cairo_line_to(cr, right, y); cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    const std::string s = tick_label(t, ay.log);
    cairo_text_extents_t e; cairo_text_extents(cr, s.c_str(), &e);
    cairo_move_to(cr, left - e.width - 8, y + 4); cairo_show_text(cr, s.c_str());
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_rectangle(cr, left, top, right - left, bottom - top);
  cairo_stroke(cr);

  // Series, clipped to the plot area.
  cairo_save(cr);
  cairo_rectangle(cr, left, top, right - left, bottom - top);
  cairo_clip(cr);
  for (const auto& s : f.series) {
    cairo_set_source_rgb(cr, s.rgb[0], s.rgb[1], s.rgb[2]);
    cairo_set_line_width(cr, 2.0);
    const double dash[] = {6.0, 4.0};
    cairo_set_dash(cr, dash, s.dashed ? 2 : 0, 0);
    bool pen = false;
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      const bool ok = std::isfinite(s.x[i]) && std::isfinite(s.y[i]) &&
                      (!ax.log || s.x[i] > 0) && (!ay.log || s.y[i] > 0);
      if (!ok) { pen = false; continue; }
      const double x = ax.map(s.x[i], left, right), y = ay.map(s.y[i], bottom, top);
      if (s.markers) {
        cairo_new_sub_path(cr);
        cairo_arc(cr, x, y, 2.5, 0, 2 * M_PI);
        cairo_fill(cr);
      } else if (!pen) {
        cairo_move_to(cr, x, y);
        pen = true;
      } else {
        cairo_line_to(cr, x, y);
      }
    }
    if (!s.markers) cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0);
  }
  cairo_restore(cr);

  // Title and labels.
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_font_size(cr, 16);
  cairo_move_to(cr, left, 30); cairo_show_text(cr, f.title.c_str());
  cairo_set_font_size(cr, 13);
  cairo_text_extents_t e; cairo_text_extents(cr, f.x_label.c_str(), &e);
  cairo_move_to(cr, (left + right) / 2 - e.width / 2, H - 20); cairo_show_text(cr, f.x_label.c_str());
  cairo_save(cr);
  cairo_text_extents(cr, f.y_label.c_str(), &e);
  cairo_move_to(cr, 22, (top + bottom) / 2 + e.width / 2);
  cairo_rotate(cr, -M_PI / 2);
  cairo_show_text(cr, f.y_label.c_str());
  cairo_restore(cr);

  // Legend (top right inside the plot).
  cairo_set_font_size(cr, 12);
  double ly = top + 18;
  for (const auto& s : f.series) {
    if (s.label.empty()) continue;
    cairo_text_extents(cr, s.label.c_str(), &e);
    const double lx = right - e.width - 40;
    cairo_set_source_rgb(cr, s.rgb[0], s.rgb[1], s.rgb[2]);
    cairo_set_line_width(cr, 2.0);
    const double dash[] = {6.0, 4.0};
    cairo_set_dash(cr, dash, s.dashed ? 2 : 0, 0);
    cairo_move_to(cr, lx, ly - 4); cairo_line_to(cr, lx + 24, ly - 4); cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_move_to(cr, lx + 30, ly); cairo_show_text(cr, s.label.c_str());
    ly += 17;
  }

  // Colour swatches.
  double sy = top;
  for (const auto& sw : f.swatches) {
    const double sx = W - swatch_w;
    cairo_set_source_rgb(cr, sw.rgb[0], sw.rgb[1], sw.rgb[2]);
    cairo_rectangle(cr, sx, sy, 120, 90);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_rectangle(cr, sx, sy, 120, 90);
    cairo_set_line_width(cr, 1.0);
    cairo_stroke(cr);
    cairo_move_to(cr, sx, sy + 106);
    cairo_show_text(cr, sw.label.c_str());
    sy += 125;
  }
}

}  // namespace

namespace {

// Draws with `paint` on a width x height surface written to `path` (PNG or SVG by the
// extension), atomically.
template <class Paint>
void write(const std::string& path, int width, int height, Paint&& paint) {
  const std::string ext = util::io::extension(path);
  if (ext != "png" && ext != "svg")
    throw InputError("plot = '" + path + "' has an unsupported extension: use .png or .svg");
  util::io::write_via_temporary(path, [&](const std::string& tmp) {
    cairo_surface_t* surface =
        ext == "png" ? cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height)
                     : cairo_svg_surface_create(tmp.c_str(), width, height);
    cairo_t* cr = cairo_create(surface);
    paint(cr);
    cairo_destroy(cr);
    cairo_status_t st = CAIRO_STATUS_SUCCESS;
    if (ext == "png") st = cairo_surface_write_to_png(surface, tmp.c_str());
    cairo_surface_finish(surface);
    if (st == CAIRO_STATUS_SUCCESS) st = cairo_surface_status(surface);
    cairo_surface_destroy(surface);
    if (st != CAIRO_STATUS_SUCCESS)
      throw InputError(path + ": cannot write plot: " + cairo_status_to_string(st));
  });
}

constexpr double kCellW = 120, kCellH = 78, kLabelW = 110, kTop = 70, kCaptionH = 18;

// A white page with its title at (12, baseline), 16 px sans-serif.
void page_with_title(cairo_t* cr, const std::string& title, double baseline) {
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_font_size(cr, 16);
  cairo_move_to(cr, 12, baseline);
  cairo_show_text(cr, title.c_str());
}

void draw_grid(cairo_t* cr, const SwatchGrid& g, double W, double H) {
  page_with_title(cr, g.title, 26);
  cairo_set_font_size(cr, 13);
  cairo_text_extents_t e;
  for (std::size_t j = 0; j < g.columns.size(); ++j) {
    cairo_text_extents(cr, g.columns[j].c_str(), &e);
    cairo_move_to(cr, kLabelW + (double(j) + 0.5) * kCellW - e.width / 2, kTop - 10);
    cairo_show_text(cr, g.columns[j].c_str());
  }
  const double row_h = kCellH + kCaptionH + 8;
  for (std::size_t i = 0; i < g.rows.size(); ++i) {
    const double y = kTop + double(i) * row_h;
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_font_size(cr, 13);
    cairo_move_to(cr, 12, y + kCellH / 2 + 4);
    cairo_show_text(cr, g.rows[i].c_str());
    for (std::size_t j = 0; j < g.columns.size(); ++j) {
      const SwatchGrid::Cell& c = g.cells.at(i * g.columns.size() + j);
      const double x = kLabelW + double(j) * kCellW + 4, w = kCellW - 8;
      cairo_set_source_rgb(cr, c.left[0], c.left[1], c.left[2]);
      cairo_rectangle(cr, x, y, c.right ? w / 2 : w, kCellH);
      cairo_fill(cr);
      if (c.right) {
        cairo_set_source_rgb(cr, (*c.right)[0], (*c.right)[1], (*c.right)[2]);
        cairo_rectangle(cr, x + w / 2, y, w / 2, kCellH);
        cairo_fill(cr);
      }
      cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
      cairo_set_font_size(cr, 11);
      cairo_move_to(cr, x, y + kCellH + 14);
      cairo_show_text(cr, c.caption.c_str());
    }
  }
  cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
  cairo_set_font_size(cr, 11);
  double y = H - 12.0 - 15.0 * double(std::count(g.note.begin(), g.note.end(), '\n'));
  std::size_t start = 0;
  while (start <= g.note.size()) {  // one line per '\n'
    const std::size_t end = std::min(g.note.find('\n', start), g.note.size());
    const std::string line = g.note.substr(start, end - start);
    cairo_move_to(cr, 12, y);
    cairo_show_text(cr, line.c_str());
    y += 15;
    start = end + 1;
  }
  (void)W;
}

// Anchors of the maps' scale (sRGB-encoded), evenly spaced in t: lightness rises throughout, so
// the order of values reads in grey too.
constexpr std::array<std::array<double, 3>, 5> kMapAnchors{{
    {0.20, 0.05, 0.35}, {0.17, 0.30, 0.55}, {0.10, 0.55, 0.55}, {0.45, 0.75, 0.30}, {0.98, 0.90, 0.15}}};

constexpr double kMapTop = 48, kMapTitleH = 22, kMapBarH = 34, kMapGap = 16;

void draw_maps(cairo_t* cr, const MapSheet& sheet, const std::vector<std::pair<int, int>>& sizes, int rows) {
  page_with_title(cr, sheet.title, 28);
  const double cell_w = sheet.panel + kMapGap;
  double row_h = 0;
  for (const auto& [w, h] : sizes) row_h = std::max(row_h, kMapTitleH + h + kMapBarH + kMapGap);
  for (std::size_t k = 0; k < sheet.panels.size(); ++k) {
    const MapPanel& m = sheet.panels[k];
    const auto [w, h] = sizes[k];
    const double x0 = 12 + double(k % static_cast<std::size_t>(sheet.columns)) * cell_w;
    const double y0 = kMapTop + double(k / static_cast<std::size_t>(sheet.columns)) * row_h;
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_font_size(cr, 13);
    cairo_move_to(cr, x0, y0 + 15);
    cairo_show_text(cr, m.title.c_str());
    // The map, box-averaged to w x h pixels.
    cairo_surface_t* img = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
    cairo_surface_flush(img);
    unsigned char* data = cairo_image_surface_get_data(img);
    const int stride = cairo_image_surface_get_stride(img);
    const double span = m.hi > m.lo ? m.hi - m.lo : 1.0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const int sx0 = x * m.width / w, sx1 = std::max(sx0 + 1, (x + 1) * m.width / w);
        const int sy0 = y * m.height / h, sy1 = std::max(sy0 + 1, (y + 1) * m.height / h);
        double sum = 0;
        int n = 0;
        bool finite = true;
        for (int yy = sy0; yy < sy1; ++yy)
          for (int xx = sx0; xx < sx1; ++xx) {
            const float v = m.values[static_cast<std::size_t>(yy) * static_cast<std::size_t>(m.width) + static_cast<std::size_t>(xx)];
            if (!std::isfinite(v)) finite = false;
            sum += v;
            ++n;
          }
        const std::array<double, 3> c = finite ? map_colour((sum / n - m.lo) / span) : std::array<double, 3>{0.5, 0.5, 0.5};
        auto* px = reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride) + x;
        *px = (static_cast<std::uint32_t>(std::lround(c[0] * 255)) << 16) |
              (static_cast<std::uint32_t>(std::lround(c[1] * 255)) << 8) | static_cast<std::uint32_t>(std::lround(c[2] * 255));
      }
    cairo_surface_mark_dirty(img);
    cairo_set_source_surface(cr, img, x0, y0 + kMapTitleH);
    cairo_paint(cr);
    cairo_surface_destroy(img);
    // The colour bar and its range.
    const double by = y0 + kMapTitleH + h + 6;
    const int steps = 64;
    for (int i = 0; i < steps; ++i) {
      const auto c = map_colour((i + 0.5) / steps);
      cairo_set_source_rgb(cr, c[0], c[1], c[2]);
      cairo_rectangle(cr, x0 + w * double(i) / steps, by, w / double(steps) + 0.5, 10);
      cairo_fill(cr);
    }
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    cairo_set_font_size(cr, 11);
    char lo[32], hi[32];
    std::snprintf(lo, sizeof lo, "%.4g", m.lo);
    std::snprintf(hi, sizeof hi, "%.4g", m.hi);
    cairo_move_to(cr, x0, by + 23);
    cairo_show_text(cr, lo);
    cairo_text_extents_t e;
    cairo_text_extents(cr, hi, &e);
    cairo_move_to(cr, x0 + w - e.width - e.x_bearing, by + 23);
    cairo_show_text(cr, hi);
  }
  cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
  cairo_set_font_size(cr, 11);
  cairo_move_to(cr, 12, kMapTop + rows * row_h + 4);
  cairo_show_text(cr, sheet.note.c_str());
}

}  // namespace

std::array<double, 3> map_colour(double t) {
  if (!(t > 0)) t = 0;  // (NaN too)
  if (t > 1) t = 1;
  const double u = t * double(kMapAnchors.size() - 1);
  const std::size_t i = std::min(kMapAnchors.size() - 2, static_cast<std::size_t>(u));
  const double f = u - double(i);
  std::array<double, 3> c{};
  for (std::size_t k = 0; k < 3; ++k) c[k] = kMapAnchors[i][k] + f * (kMapAnchors[i + 1][k] - kMapAnchors[i][k]);
  return c;
}

void save(const MapSheet& sheet, const std::string& path) {
  if (util::io::extension(path) != "png")
    throw InputError("preview = '" + path + "': maps are written as .png");
  if (sheet.panels.empty() || sheet.columns < 1 || sheet.panel < 8)
    throw InputError("map sheet: no maps, or a panel under 8 pixels");
  std::vector<std::pair<int, int>> sizes;
  for (const MapPanel& m : sheet.panels) {
    if (m.width < 1 || m.height < 1 || m.values.size() != static_cast<std::size_t>(m.width) * static_cast<std::size_t>(m.height))
      throw InputError("map sheet: map '" + m.title + "' has " + std::to_string(m.values.size()) + " values for " +
                       std::to_string(m.width) + " x " + std::to_string(m.height));
    const int w = std::min(m.width, sheet.panel);
    const int h = std::max(1, static_cast<int>(std::lround(double(m.height) * w / m.width)));
    sizes.emplace_back(w, h);
  }
  const int cols = std::min(sheet.columns, static_cast<int>(sheet.panels.size()));
  const int rows = (static_cast<int>(sheet.panels.size()) + sheet.columns - 1) / sheet.columns;
  double row_h = 0;
  for (const auto& [w, h] : sizes) row_h = std::max(row_h, kMapTitleH + h + kMapBarH + kMapGap);
  const int width = static_cast<int>(12 + cols * (sheet.panel + kMapGap));
  const int height = static_cast<int>(kMapTop + rows * row_h + 16);
  write(path, width, height, [&](cairo_t* cr) { draw_maps(cr, sheet, sizes, rows); });
}

void save(const Figure& fig, const std::string& path) {
  write(path, fig.width, fig.height, [&](cairo_t* cr) { draw(cr, fig); });
}

void save(const SwatchGrid& grid, const std::string& path) {
  if (grid.cells.size() != grid.rows.size() * grid.columns.size())
    throw InputError("swatch grid: " + std::to_string(grid.cells.size()) + " cells for " +
                     std::to_string(grid.rows.size()) + " x " + std::to_string(grid.columns.size()));
  const int lines = grid.note.empty() ? 0 : 1 + static_cast<int>(std::count(grid.note.begin(), grid.note.end(), '\n'));
  const int width = static_cast<int>(kLabelW + kCellW * double(grid.columns.size()) + 12);
  const int height = static_cast<int>(kTop + (kCellH + kCaptionH + 8) * double(grid.rows.size()) + 10 + 15 * lines);
  write(path, width, height, [&](cairo_t* cr) { draw_grid(cr, grid, width, height); });
}

}  // namespace skin::plot
