// Linked into every benchmark binary: the allocator settings of the `skin` executable and the
// Python module (skin/util/allocator.hpp), so that the benchmarks time what users run.
#include "skin/util/allocator.hpp"

namespace {
const bool kKept = (skin::util::keep_matrix_memory(), true);
}  // namespace
