// The compiled kernels of lenslab: the samplers of lenslab.warp (single-tap bilinear, cached taps, the
// footprint prefilter). Each works on one band of output rows and is called with the GIL released, so
// the engine runs one band per thread. Every kernel has a NumPy reference in lenslab/warp/kernels/reference.py
// that gives the same bits (tests/warp/test_native_kernels.py).
#pragma once

#include <cmath>
#include <cstdint>

namespace lenslab {

// Fold tap (column i, row j) into 0 <= i < w, 0 <= j < h by the border rules (lenslab.warp.seam.fold_index).
inline void fold_index(int64_t& i, int64_t& j, int64_t w, int64_t h, bool wrap, bool top, bool bottom) {
    if (j < 0) {
        if (top) { j = -1 - j; i += w / 2; }
        if (j < 0) j = 0;
    }
    if (j >= h) {
        if (bottom) { j = 2 * h - 1 - j; i += w / 2; }
        if (j >= h) j = h - 1;
        if (j < 0) j = 0;
    }
    if (wrap) { i %= w; if (i < 0) i += w; }
    else if (i < 0) i = 0;
    else if (i >= w) i = w - 1;
}

struct Border { bool wrap, top, bottom; };

// A map position as the samplers read it: beyond +-2^40 (inf included) at +-2^40, NaN at -2^40, so that a
// hostile map (1e30, or NaN marked valid) reads an edge pixel and never converts an out-of-range float to an
// integer (undefined behaviour); the separable samplers clamp the same way (separable.cpp).
constexpr float FAR_POS = 1099511627776.0f;  // 2^40: exact in float32; every tap beyond folds to the same pixel
inline float clamp_pos(float v) { return v >= -FAR_POS ? (v > FAR_POS ? FAR_POS : v) : -FAR_POS; }

// floor() for a position clamp_pos has bounded (|v| <= 2^40), without a libm call on CPUs before SSE4.1; the
// same value as std::floor but for -0.0 (gives +0.0, which no lerp or weight can tell apart)
inline float ffloor(float v) {
    float t = float(int64_t(v));
    return t > v ? t - 1.0f : t;
}
inline double dfloor(double v) {
    double t = double(int64_t(v));
    return t > v ? t - 1.0 : t;
}

// The bilinear value of four taps as the weighted sum in float64, a tap of weight 0 left out: finite for finite
// taps of any size (|value| <= the largest |tap|), where float32 lerps pass float32's range (b - a of taps of
// opposite signs beyond 1.7e38 is inf, and inf - inf NaN); an infinite tap of weight 0 is not read.
inline float lerp_wide(float a, float b, float c, float d, float tx, float ty) {
    const double wx = tx, wy = ty, ux = 1.0 - wx, uy = 1.0 - wy;
    const double w[4] = {ux * uy, wx * uy, ux * wy, wx * wy};
    const float v[4] = {a, b, c, d};
    double s = 0.0;
    for (int k = 0; k < 4; ++k)
        if (w[k] != 0.0) s += w[k] * double(v[k]);
    return float(s);  // within one float64 rounding of a convex combination: never beyond the largest float32
}

// One pixel's nc channels, bilinear in float32 lerps from four flat tap offsets (lenslab.warp.kernels.reference
// bilinear1); a value the float32 steps make non-finite is made again by lerp_wide (never for taps below 1.7e38).
inline void lerp(const float* flat, uint64_t p00, uint64_t p10, uint64_t p01, uint64_t p11, float tx, float ty,
                 int64_t nc, float* o) {
    for (int64_t ch = 0; ch < nc; ++ch) {
        float a = flat[p00 + ch], b = flat[p01 + ch];
        float upper = a + tx * (flat[p10 + ch] - a);
        float lower = b + tx * (flat[p11 + ch] - b);
        float v = upper + ty * (lower - upper);
        if (__builtin_expect(!(v - v == 0.0f), 0))  // inf or NaN: the float32 steps overflowed (or a tap is inf)
            v = lerp_wide(a, flat[p10 + ch], b, flat[p11 + ch], tx, ty);
        o[ch] = v;
    }
}

// Flat offsets of the 2x2 taps with top-left (i0, j0), folded where they leave the image.
inline void corners(int64_t i0, int64_t j0, int64_t sw, int64_t sh, int64_t nc, Border b, uint64_t* p) {
    if (i0 >= 0 && j0 >= 0 && i0 + 1 < sw && j0 + 1 < sh) {
        uint64_t p00 = uint64_t((j0 * sw + i0) * nc);
        p[0] = p00; p[1] = p00 + nc; p[2] = p00 + sw * nc; p[3] = p00 + sw * nc + nc;
        return;
    }
    for (int k = 0; k < 4; ++k) {
        int64_t i = i0 + (k & 1), j = j0 + (k >> 1);
        fold_index(i, j, sw, sh, b.wrap, b.top, b.bottom);
        p[k] = uint64_t((j * sw + i) * nc);
    }
}

}  // namespace lenslab
