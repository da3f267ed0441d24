// AgX per channel (lenslab.tone.agx) on interleaved float32 RGB pixels: see agx_pixels. Compiled like the warp
// kernels (multiply-adds fused where the CPU has them).
#include <algorithm>
#include <cstdint>
#include <cstring>

#include "tone.h"

namespace lenslab {
namespace {

template <typename To, typename From> inline To bits_as(From v) {
    static_assert(sizeof(To) == sizeof(From));
    To t;
    std::memcpy(&t, &v, sizeof(To));
    return t;
}

constexpr float ROUND = 12582912.0f;  // 1.5 2^23: (x + ROUND) - ROUND is x rounded to an integer (|x| < 2^22)

// x = 2^e m (x a positive normal float32) with m in [sqrt(1/2), sqrt(2)); e is an integer, held as a float
inline void split(float x, float& e, float& m) {
    const uint32_t b = bits_as<uint32_t>(x);
    const float mm = bits_as<float>((b & 0x007FFFFFu) | 0x3F800000u);
    const float ee = float(int32_t(b >> 23) - 127);
    const bool high = mm > 1.41421356f;
    m = high ? mm * 0.5f : mm;
    e = high ? ee + 1.0f : ee;
}

// log2 m for m in [sqrt(1/2), sqrt(2)): (2 / ln 2) atanh(r), r = (m - 1) / (m + 1), |r| <= 0.1716, by the
// atanh series to r^9 (the first term left out is below 1.1e-9; float32 rounding leaves about 1e-7 relative)
inline float log2_mantissa(float m) {
    const float r = (m - 1.0f) / (m + 1.0f), r2 = r * r;
    float s = 1.0f / 9;
    s = s * r2 + 1.0f / 7;
    s = s * r2 + 1.0f / 5;
    s = s * r2 + 1.0f / 3;
    s = s * r2 + 1.0f;
    return (2.0f * 1.44269504f) * (r * s);
}

// y^2.2 for y in [2^-60, 1], without a log or an exp: y = 2^e m as in split, so y^2.2 = 2^(2e + q) 2^(j/5) m^2.2
// with q = floor(e / 5) and j = e - 5q in 0..4. m^2.2 is the degree-7 Chebyshev interpolant of m^2.2 on
// [sqrt(1/2), sqrt(2)] written in powers of u = m - 1 (1.9e-9 from m^2.2 there); 2^(j/5) one of five float32
// constants, chosen without a branch or a table (each partial sum below is one of the constants exactly);
// 2^(2e + q) is built from its bits. About 2 float32 roundings of the result in all.
inline float pow22(float y) {
    float e, m;
    split(y, e, m);
    const float u = m - 1.0f;
    float p = 0.00132209616f;
    p = p * u - 0.00310870652f;
    p = p * u + 0.00639312450f;
    p = p * u - 0.0175929484f;
    p = p * u + 0.0879971838f;
    p = p * u + 1.31999989f;
    p = p * u + 2.20000003f;
    p = p * u + 1.0f;
    const float q = ((e - 2.0f) * 0.2f + ROUND) - ROUND;  // floor(e / 5) for an integer e <= 0
    const float j = e - 5.0f * q;
    constexpr float f1 = 1.14869835f, f2 = 1.31950791f, f3 = 1.51571657f, f4 = 1.74110113f;  // 2^(j/5)
    const float fifth = (((1.0f + float(j >= 1.0f) * (f1 - 1.0f)) + float(j >= 2.0f) * (f2 - f1))
                         + float(j >= 3.0f) * (f3 - f2)) + float(j >= 4.0f) * (f4 - f3);
    return (p * fifth) * bits_as<float>(uint32_t(int32_t(2.0f * e + q) + 127) << 23);
}

}  // namespace

// AgX on n interleaved pixels: v = m_in rgb in float32 (the inset matrix with the exposure and 2^-min EV folded
// in, as the NumPy kernel has it), w = log2(clamp(v, 1, top)) = e + log2 m with the sum in float64 (a float32
// w near 16 would be 1e-6 off), the sigmoid's 6th-order polynomial in w (coefficients of w^6 first) and the
// outset matrix in float64 (the polynomial's large alternating terms cancel), then y^2.2 in float32 on
// clamp(y, floor, 1), minus floor^2.2 so that y <= 0 gives exactly 0. Power must be 2.2 (checked by the
// binding). Each step is its own loop over a chunk of values, interleaved as the pixels come (only the two
// matrices see pixels): GCC vectorises these loops, and not the steps fused into one (the clamps' selects
// stop it).
uint32_t agx_pixels(const float* src, float* dst, int64_t n, const double* m_in, const double* m_out,
                    const double* poly, double top, double floor_, double) {
    alignas(64) float a[3 * TONE_CHUNK], ex[3 * TONE_CHUNK], y[3 * TONE_CHUNK];
    alignas(64) double w[3 * TONE_CHUNK], s[3 * TONE_CHUNK];  // m pixels, interleaved as they come
    float mi[9];
    for (int i = 0; i < 9; ++i) mi[i] = float(m_in[i]);
    const float hi = float(top), lo = float(floor_), offset = pow22(lo);
    const double c0 = poly[0], c1 = poly[1], c2 = poly[2], c3 = poly[3], c4 = poly[4], c5 = poly[5], c6 = poly[6];
    const uint32_t* bits = reinterpret_cast<const uint32_t*>(src);
    uint32_t worst = 0;
    for (int64_t s0 = 0; s0 < n; s0 += TONE_CHUNK) {
        const int64_t m = std::min(TONE_CHUNK, n - s0), k = 3 * m;
        const float* p = src + 3 * s0;
        const uint32_t* q = bits + 3 * s0;
        for (int64_t i = 0; i < k; ++i) worst = greater(worst, q[i]);
        for (int64_t i = 0; i < m; ++i) {
            const float r = p[3 * i], g = p[3 * i + 1], b = p[3 * i + 2];
            for (int c = 0; c < 3; ++c) a[3 * i + c] = (mi[3 * c] * r + mi[3 * c + 1] * g) + mi[3 * c + 2] * b;
        }
        for (int64_t i = 0; i < k; ++i) a[i] = clamp(a[i], 1.0f, hi);
        for (int64_t i = 0; i < k; ++i) {
            float e, mant;
            split(a[i], e, mant);
            ex[i] = e;
            a[i] = mant;
        }
        for (int64_t i = 0; i < k; ++i) a[i] = log2_mantissa(a[i]);
        for (int64_t i = 0; i < k; ++i) w[i] = double(ex[i]) + double(a[i]);
        for (int64_t i = 0; i < k; ++i) {
            const double x = w[i];
            double t = c0;
            t = t * x + c1;
            t = t * x + c2;
            t = t * x + c3;
            t = t * x + c4;
            t = t * x + c5;
            w[i] = t * x + c6;
        }
        for (int64_t i = 0; i < m; ++i) {
            const double r = w[3 * i], g = w[3 * i + 1], b = w[3 * i + 2];
            for (int c = 0; c < 3; ++c) s[3 * i + c] = (m_out[3 * c] * r + m_out[3 * c + 1] * g) + m_out[3 * c + 2] * b;
        }
        for (int64_t i = 0; i < k; ++i) s[i] = clamp(s[i], double(lo), 1.0);
        for (int64_t i = 0; i < k; ++i) y[i] = float(s[i]);
        float* o = dst + 3 * s0;
        for (int64_t i = 0; i < k; ++i) o[i] = pow22(y[i]) - offset;
    }
    return worst;
}

}  // namespace lenslab
