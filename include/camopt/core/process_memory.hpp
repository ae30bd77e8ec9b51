#pragma once
// glibc gives freed memory above its trim threshold back to the kernel and serves large
// blocks by mmap, so a program that runs sweep after sweep (an optimiser, an rpm map, the
// benchmarks) takes a fresh page fault for every 4 KiB of every result table: the CVVL's
// 17-position all-outputs sweep, ~1100 faults and ~2 ms of its ~20 (bench/README.md).
// Keeping freed memory in the heap removes them. Called once by a program's main(), never
// by the library.
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace camopt {

inline void keep_freed_memory() noexcept {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 32 << 20);   // [bytes] glibc's largest allowed value on 64-bit
  mallopt(M_TRIM_THRESHOLD, 512 << 20);  // [bytes]
#endif
}

}  // namespace camopt
