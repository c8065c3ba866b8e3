#pragma once
// The paper's figures (`skin figure`): the parameter sweeps of DJ06 Figs 3-8 (model-notes
// section 7) as close-up crops of a face (cheek and nose, one crop per parameter set, the same
// camera and lights for each), and Fig. 10 (textured faces, a back-lit ear, several lights).
// Each cell is a scene of its own; they are rendered one after another and assembled into a
// grid, labelled underneath (docs/renderer.md, "Figures").
#include <functional>
#include <string>
#include <vector>

#include "skin/physics/skin_parameters.hpp"
#include "skin/render/image.hpp"
#include "skin/render/scene.hpp"

namespace skin::render {

// Layout of a figure: grid size, title, and per cell (row-major) its label and skin parameters.
struct FigureLayout {
  int number = 0;
  int columns = 1, rows = 1;
  std::string title;
  std::vector<std::string> labels;
  std::vector<physics::SkinParameters> parameters;
};

// The figures there are: 3, 4, 5, 6, 7, 8, 10.
const std::vector<int>& figure_numbers();
// Not one of the paper's: `skin figure tones`, a face per tone preset (monk-01 ... monk-10, the
// Monk Skin Tone scale fitted under D65; docs/tone-presets.md), in two rows of five. Its number
// for figure_layout() and describe_figure().
inline constexpr int kTonesFigure = 0;

// The cells of figure `number` with the paper's parameters. `change` (optional; the CLI's
// --preset and parameter flags) changes each cell's set; a sweep's own parameter then keeps the
// paper's value of the cell (so `--preset african` sweeps oiliness on African skin). Throws
// InputError for a number not in figure_numbers() or kTonesFigure. Fig. 8 shows the paper's three
// skin types above three tone presets spanning the same range (monk-02, monk-06, monk-10).
FigureLayout figure_layout(int number, const std::function<physics::SkinParameters(const physics::SkinParameters&)>& change = {});

// The scenes of a figure, one per cell of its layout.
struct Figure {
  FigureLayout layout;
  std::vector<Scene> cells;
  bool on_mesh = false;  // false: spheres (and a thin fin for the ear), no mesh given
};
// The same, described: the CLI's --solver and --spectral edit the cells before build(), which
// computes each distinct skin of all the cells once.
struct FigureDescription {
  FigureLayout layout;
  std::vector<SceneDescription> cells;
  bool on_mesh = false;
  Figure build(const util::ProgressCallback& progress = {}) const;  // (SceneDescription::build)
  BuildWork build_work() const;
};
// Describes the cells on the face mesh `mesh_path` (OBJ, glTF, GLB; placed by its bounding box
// in the frame of the Lee Perry-Smith head, 22 mm per unit as examples/head.json), or on spheres
// when `mesh_path` is empty. `albedo_texture` (Fig. 10 only; empty: none) is the mesh's colour
// texture, normalised by the R_d colour of caucasian skin (DJ06 section 3.6).
FigureDescription describe_figure(int number, const std::string& mesh_path, const std::string& albedo_texture = "",
                                  const std::function<physics::SkinParameters(const physics::SkinParameters&)>& change = {});
// describe_figure(...).build().
Figure make_figure(int number, const std::string& mesh_path, const std::string& albedo_texture = "",
                   const std::function<physics::SkinParameters(const physics::SkinParameters&)>& change = {});

// Renders every cell with `settings` (its width and height are a cell's; a time budget is split
// evenly over the cells) and assembles the cells into the layout's grid, without labels.
// `stats`: totals over the cells, the skin mask of the grid and the relative RMS error over all
// skin pixels (RenderStats::estimated_error, from the cells' own estimates).
Image render_figure(const Figure& figure, const RenderSettings& settings, RenderStats* stats = nullptr,
                    const Progress& progress = {});

// Adds a title line on top and each cell's label under it.
Image annotate_figure(const Image& rendered, const FigureLayout& layout);

}  // namespace skin::render
