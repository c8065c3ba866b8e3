#pragma once
// How a library reports progress: it never draws; it calls back, and the application presents
// (src/app/progress.hpp draws a bar on a terminal).
#include <cstddef>
#include <functional>

namespace skin::util {

// progress(done, total): `done` of `total` units of work (photons, table nodes, colours, cases)
// are finished. Called from the thread that called the library function, never concurrently,
// with `done` non-decreasing and `done == total` on the last call. An empty function is never
// called, so a library pays nothing when nobody watches.
using ProgressCallback = std::function<void(std::size_t done, std::size_t total)>;

}  // namespace skin::util
