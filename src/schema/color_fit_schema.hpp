#pragma once
// The schemas of `skin fit --hex / --srgb` and `skin fit --texture` (schema.hpp).
#include <string>

#include "schema.hpp"
#include "skin/fit/color_fit.hpp"

namespace skin::schema {

// The colour fit of `target` (linear sRGB of the 8-bit colour asked for): the target and the
// fitted colour (hex, CIELAB under D65), every parameter, the colour error, the prior on
// melanin_blend.
Result color_fit_result(const fit::ColorFitResult& r, const color::Rgb& target, double melanin_blend_prior,
                        double melanin_blend_weight);
// The texture fit's summary: the size of the maps, their channels and colour error; and the same
// with the texture read and the maps' file written (the command's).
json texture_fit_document(const fit::ParameterMaps& maps);
Result texture_fit_result(const fit::ParameterMaps& maps, const std::string& texture,
                          const std::string& output);

}  // namespace skin::schema
