#include "skin/util/allocator.hpp"

#include <cstdlib>  // defines __GLIBC__ where the C library is glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace skin::util {

void keep_matrix_memory() {
#if defined(__GLIBC__)
  // Measured (docs/validation/accurate-solver-history.md, sec. 7): one frequency-domain skin
  // profile 1.01 -> 0.57 s.
  mallopt(M_MMAP_THRESHOLD, 4 << 20);
  mallopt(M_TRIM_THRESHOLD, 32 << 20);
#endif
}

}  // namespace skin::util
