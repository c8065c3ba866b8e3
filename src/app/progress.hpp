#pragma once
// The application's one progress bar. Libraries report progress through callbacks
// (skin::util::ProgressCallback, skin::render::Progress); the application draws it here.
#include <functional>
#include <string>

#include "skin/util/progress.hpp"

namespace skin::cli {

// A bar on stderr, redrawn in place:
//   [###############                         ]  37%  370000/1000000 photons  2.1 s
// `unit` names what is counted ("photons", "nodes", "distinct colours"); with "" the counts are
// left out. Redrawn when the percentage changes (at most every 0.1 s otherwise), ended with a
// newline when done reaches total; a later call starts a new bar. The seconds are counted from
// the callback's creation or, for a new bar, its first call. When stderr is not a terminal the
// callback is empty (nothing is drawn, and the libraries skip the calls), so logs and pipes get
// no control characters. The callback may be called from any thread (calls are serialised).
util::ProgressCallback progress_bar(const std::string& unit);

// The same bar for a fraction of the work in [0, 1] (the renderer's progress).
std::function<void(double fraction)> progress_fraction_bar();

}  // namespace skin::cli
