// Flush-to-zero and denormals-are-zero for the calling thread while in scope (x86's MXCSR;
// nothing elsewhere). Embree's documentation asks for both on every thread that casts rays:
// a denormal operand costs a float operation about a hundred cycles. Restores the thread's
// previous mode on exit, so a pooled worker thread leaves the scope as it entered it.
#pragma once

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

namespace holo {

class FlushDenormals {
 public:
#if defined(__SSE2__)
  // 0x8040: the FTZ (bit 15) and DAZ (bit 6) flags of MXCSR.
  FlushDenormals() : saved_(_mm_getcsr()) {
    _mm_setcsr(saved_ | 0x8040u);
  }
  ~FlushDenormals() {
    _mm_setcsr(saved_);
  }
#else
  FlushDenormals() = default;
#endif
  FlushDenormals(const FlushDenormals&) = delete;
  FlushDenormals& operator=(const FlushDenormals&) = delete;

 private:
#if defined(__SSE2__)
  unsigned saved_;
#endif
};

}  // namespace holo
