#pragma once
// The schema of `skin fit --spectrum`'s output (schema.hpp), for the command and the web page.
#include <string>

#include "schema.hpp"
#include "skin/fit/fit.hpp"

namespace skin::schema {

// The fit of spectrum `m` by `solver`: the JSON document (input, parameters, uncertainty, rms,
// the fitted samples, ...), the CSV columns (every free parameter and its uncertainty, rms) and
// the table text.
// `port_radius` > 0: the fit's model was the light collected through a port of that radius [mm]
// around a beam of `beam_radius` (fit::forward_model_through_port); 0: R_d (JSON null).
Result spectrum_fit_result(const fit::MeasuredSpectrum& m, const fit::FitResult& r,
                           const std::string& solver, bool includes_specular, double port_radius = 0,
                           double beam_radius = 0);

}  // namespace skin::schema
