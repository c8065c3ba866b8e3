#pragma once
// The renderer's images are the project's (skin/image/image.hpp): linear RGB floats, row 0 at
// the top, written as OpenEXR (linear float) or PNG (sRGB 8 bits after an exposure in stops).
#include "skin/image/image.hpp"

namespace skin::render {

using image::Image;
using image::read_image;
using image::write_image;
using image::ToneMap;

}  // namespace skin::render
