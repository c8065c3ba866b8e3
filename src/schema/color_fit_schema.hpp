#pragma once
// The schemas of `skin fit --hex / --srgb` and `skin fit --texture` (schema.hpp).
#include <string>

#include "schema.hpp"
#include "skin/fit/color_fit.hpp"

namespace skin::schema {

// The colour fit: the target and the fitted colour (their hex from `target` and `fitted`, the
// colours' summaries under D65), every parameter, the colour error, the prior on melanin_blend.
Result color_fit_result(const fit::ColorFitResult& r, const color::ColorSummary& target,
                        const color::ColorSummary& fitted, double melanin_blend_prior,
                        double melanin_blend_weight);
// The texture fit's summary: the maps of `texture` written to `output` and their colour error.
Result texture_fit_result(const fit::ParameterMaps& maps, const std::string& texture,
                          const std::string& output);

}  // namespace skin::schema
