// The tone kernels of src/native/tone.cpp and tone_agx.cpp (bound in tone.cpp).
#pragma once
#include <cstdint>

namespace lenslab {

// min and max by value (std::min's references keep GCC from vectorising some loops); on the clean values
// the kernels see they are NumPy's fmin, fmax and clip
template <typename T> inline T lesser(T a, T b) { return b < a ? b : a; }
template <typename T> inline T greater(T a, T b) { return a < b ? b : a; }
template <typename T> inline T clamp(T v, T lo, T hi) { return lesser(greater(v, lo), hi); }

constexpr int64_t TONE_CHUNK = 256;  // pixels a kernel holds on the stack at a time

// AgX on n interleaved float32 RGB pixels (tone_agx.cpp); returns the largest bit pattern read.
uint32_t agx_pixels(const float* src, float* dst, int64_t n, const double* m_in, const double* m_out,
                    const double* poly, double top, double floor_, double power);

}  // namespace lenslab
