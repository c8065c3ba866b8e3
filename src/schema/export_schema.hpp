#pragma once
// The schema of `skin export`'s fit report (schema.hpp): FILE.fit.json, the web page's "report"
// and Python's export()["report"].
#include <string>
#include <string_view>
#include <vector>

#include "schema.hpp"
#include "skin/export/export.hpp"

namespace skin::schema {

// The fit report of an export: the target and its model, the parameters, the solver, the units,
// `files` (the names as given: InputError naming "output" unless UTF-8 text), whether the target
// reaches our skin, the notes, both colours, the errors, our mean radii, the target's values;
// with parameter maps the texels and the worst colour error. Numbers as the files write them
// (exporting::report_number, report_error); the parameters as given.
json fit_report_document(const exporting::FitReport& report, const physics::SkinParameters& parameters,
                         std::string_view solver, const std::vector<std::string>& files);

}  // namespace skin::schema
