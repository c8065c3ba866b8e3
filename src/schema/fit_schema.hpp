#pragma once
// The schema of `skin fit --spectrum`'s output (schema.hpp), for the command and the web page.
#include <string>

#include "schema.hpp"
#include "skin/fit/fit.hpp"

namespace skin::schema {

// The fit of spectrum `m` by `solver`: the JSON document (input, parameters, uncertainty, rms,
// the fitted samples, ...), the CSV columns (every free parameter and its uncertainty, rms) and
// the table text.
Result spectrum_fit_result(const fit::MeasuredSpectrum& m, const fit::FitResult& r,
                           const std::string& solver, bool includes_specular);

}  // namespace skin::schema
