// What the video passes (video.cpp, video_ycbcr.cpp) share: argument checks, bands of rows on threads, and the
// inverse transfer function's table over float32 bit patterns.
#pragma once

#include "bind.h"

#include <algorithm>
#include <cstdint>
#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#endif
#include <cstring>
#include <stdexcept>
#include <thread>
#include <vector>

namespace lenslab_video {

using lenslab::bind::need;  // the bindings' one-line refusal (bind.h)

// fn(r0, r1) over rows [0, rows) in `threads` bands of a multiple of `align` rows; the first on the calling thread
template <typename F>
void bands(int64_t rows, int64_t threads, int64_t align, F fn) {
    int64_t n = std::max<int64_t>(1, std::min<int64_t>(threads, rows / std::max<int64_t>(align, 8)));
    int64_t per = ((rows + n - 1) / n + align - 1) / align * align;
    std::vector<std::thread> pool;
    for (int64_t r = per; r < rows; r += per) pool.emplace_back(fn, r, std::min(rows, r + per));
    fn(int64_t(0), std::min(rows, per));
    for (auto& t : pool) t.join();
}

// The inverse transfer function as a table over float32 bit patterns: knot i at the float whose bits are
// b0 + (i << shift); between knots (one binade, so linear in the bits) the code is interpolated linearly.
struct Curve {
    const float* table;
    int64_t size;
    uint32_t b0;
    int shift;
    float zero;  // the code of 0, NaN and anything below the first knot
    float operator()(float x) const {
        if (!(x > 0.0f)) return zero;  // 0, negative, NaN
        uint32_t b;
        std::memcpy(&b, &x, 4);
        if (b < b0) return zero;
        uint64_t d = uint64_t(b - b0);
        uint64_t i = d >> shift;
        if (int64_t(i) >= size - 1) return table[size - 1];  // beyond the last knot, +inf included
        float f = float(d & ((uint64_t(1) << shift) - 1)) * (1.0f / float(uint64_t(1) << shift));
        return table[i] + f * (table[i + 1] - table[i]);
    }
};

// Curve's value without branches, for loops the compiler vectorises: the same but beyond the last knot, where it
// gives the last knot's value up to one rounding (callers clamp codes to [0, 1] there: the knots end at 2^7)
inline float curve_flat(const Curve& c, float x) {
    uint32_t b;
    std::memcpy(&b, &x, 4);
    bool ok = x > 0.0f && b >= c.b0;  // NaN fails the first
    uint32_t d = ok ? b - c.b0 : 0u;
    uint32_t i = d >> c.shift;
    uint32_t last = uint32_t(c.size - 2);
    float f = float(d & ((1u << c.shift) - 1u)) * (1.0f / float(1u << c.shift));
    f = i > last ? 1.0f : f;
    i = i > last ? last : i;
    float v = c.table[i] + f * (c.table[i + 1] - c.table[i]);
    return ok ? v : c.zero;
}

// curve_flat over n values (x and out may be the same array): eight at a time with AVX2 gathers where the CPU has
// them (the compiler does not vectorise the table's gathers by itself), the same arithmetic as curve_flat
inline void curve_many(const Curve& c, const float* x, float* out, int64_t n) {
    int64_t q = 0;
#if defined(__AVX2__) && defined(__FMA__)
    const __m256i b0 = _mm256_set1_epi32(int32_t(c.b0)), last = _mm256_set1_epi32(int32_t(c.size - 2));
    const __m256i low = _mm256_set1_epi32(int32_t((1u << c.shift) - 1u));
    const __m256 scale = _mm256_set1_ps(1.0f / float(1u << c.shift)), one = _mm256_set1_ps(1.0f);
    const __m256 zero = _mm256_set1_ps(c.zero);
    const __m128i shift = _mm_cvtsi32_si128(c.shift);
    for (; q + 8 <= n; q += 8) {
        __m256 v = _mm256_loadu_ps(x + q);
        __m256i b = _mm256_castps_si256(v);
        // x > 0 (false for NaN) and its bits at least b0 (both positive as signed integers)
        __m256i ok = _mm256_and_si256(_mm256_castps_si256(_mm256_cmp_ps(v, _mm256_setzero_ps(), _CMP_GT_OQ)),
                                      _mm256_cmpgt_epi32(b, _mm256_sub_epi32(b0, _mm256_set1_epi32(1))));
        __m256i d = _mm256_and_si256(_mm256_sub_epi32(b, b0), ok);
        __m256i i = _mm256_srl_epi32(d, shift);
        __m256 f = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_and_si256(d, low)), scale);
        __m256i over = _mm256_cmpgt_epi32(i, last);
        f = _mm256_blendv_ps(f, one, _mm256_castsi256_ps(over));
        i = _mm256_min_epi32(i, last);
        __m256 t0 = _mm256_i32gather_ps(c.table, i, 4), t1 = _mm256_i32gather_ps(c.table + 1, i, 4);
        __m256 r = _mm256_fmadd_ps(f, _mm256_sub_ps(t1, t0), t0);
        _mm256_storeu_ps(out + q, _mm256_blendv_ps(zero, r, _mm256_castsi256_ps(ok)));
    }
#endif
    for (; q < n; ++q) out[q] = curve_flat(c, x[q]);
}

// NaN -> 0, +inf -> 1e4, -inf -> 0 (as numpy.nan_to_num)
inline float finite(float a) {
    return a != a ? 0.0f : (a > 3.4e38f ? 1e4f : (a < -3.4e38f ? 0.0f : a));
}

}  // namespace lenslab_video
