#pragma once
// Labelled figure grids of `skin figure` (the paper's parameter sweeps, model-notes section 7).
#include "skin/render/image.hpp"
#include "skin/render/scene.hpp"

namespace skin::render {

// Adds a title line on top and each patch's label under its cell.
Image annotate_figure(const Image& rendered, const FigureLayout& layout);

}  // namespace skin::render
