#pragma once
// Process-wide allocator settings for programs that use Spectral Skin (the `skin` executable,
// the Python module, the benchmarks call it once at start-up; a library never does it behind a
// program's back).
namespace skin::util {

// The transport solvers work on dense matrices of 64-512 rows (32 KB-2 MB each) that are made
// and freed thousands of times per profile. With glibc's defaults, blocks from 128 KB up are
// mapped and unmapped one by one and freed memory at the top of the heap is handed back to the
// system, so every such matrix costs fresh pages (page faults and zeroing), a large share of the
// time of a frequency-domain profile (docs/benchmarks.md). This keeps blocks up to 4 MB on the heap and up to 32 MB of freed
// heap in the process. No effect where the C library is not glibc (WebAssembly, other systems).
void keep_matrix_memory();

}  // namespace skin::util
