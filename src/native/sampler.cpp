// Single-tap bilinear sampling: from a map band (one or several samples per pixel) and from cached taps.
#include "kernels.h"
#include <cfloat>
#include <cmath>
#include <cstring>
#include <immintrin.h>

#include "sampler.h"

namespace lenslab {

namespace {

// samples ahead whose source rows the bilinear samplers ask the memory for: their gathers from a large source wait
// on memory, not on arithmetic (1024x1024 from 4096x2048 RGB, one thread: 19.6 ms -> 9.7 ms; 8 ahead: 11.9 ms,
// 64: 10.3 ms). A prefetch changes no value.
constexpr int64_t PREFETCH = 32;
// the cached-taps sampler, whose pixels cost less since their lerp is one vector, asks further ahead (its warp of a
// 3840x1920 clip frame into a 1920x1920 fisheye, both threads, least CPU of 40 runs: 22.1 ms at 32, 20.7 at 64, 20.9
// at 96; 512x512 from 1024x512 unchanged within 2 %)
constexpr int64_t PREFETCH_TAPS = 64;

#if defined(__FMA__)
// lerp of three channels (the taps at p00 and p01 and their right neighbours) in one SSE vector, each step the same
// fused multiply-add as lerp's: false (nothing written) where a value is not finite, for lerp's wide path. Each load
// of four floats stays inside the source: the fourth of a top tap or of p01 is a later tap's first; the last tap is
// read from one float earlier and shifted.
inline bool rgb_lerp(const float* flat, uint64_t p00, uint64_t p01, float tx, float ty, float* dst) {
    const __m128 a = _mm_loadu_ps(flat + p00), c = _mm_loadu_ps(flat + p00 + 3), b = _mm_loadu_ps(flat + p01);
    const __m128 d0 = _mm_loadu_ps(flat + p01 + 2), d = _mm_shuffle_ps(d0, d0, _MM_SHUFFLE(3, 3, 2, 1));
    const __m128 x = _mm_set1_ps(tx), y = _mm_set1_ps(ty);
    const __m128 upper = _mm_fmadd_ps(x, _mm_sub_ps(c, a), a), lower = _mm_fmadd_ps(x, _mm_sub_ps(d, b), b);
    const __m128 v = _mm_fmadd_ps(y, _mm_sub_ps(lower, upper), upper);
    if ((_mm_movemask_ps(_mm_cmpeq_ps(_mm_sub_ps(v, v), _mm_setzero_ps())) & 7) != 7) return false;
    _mm_storel_pi(reinterpret_cast<__m64*>(dst), v);
    _mm_store_ss(dst + 2, _mm_movehl_ps(v, v));
    return true;
}
#endif

// NC > 0: that many channels, known to the compiler (kept in registers); NC == 0: nc at run time
template <int NC>
void from_taps_t(const float* __restrict__ flat, int64_t sw, int64_t nc_, const uint32_t* __restrict__ off,
                 const float* __restrict__ tx, const float* __restrict__ ty, int64_t n, float* __restrict__ out,
                 float* __restrict__ alpha) {
    const int64_t nc = NC > 0 ? NC : nc_;
    const uint64_t row = uint64_t(sw * nc), step = uint64_t(nc);
    for (int64_t q = 0; q < n; ++q) {
        if (q + PREFETCH_TAPS < n && off[q + PREFETCH_TAPS] < TAP_FOLDED) {  // a sample a few ahead: both its tap rows
            const float* t = flat + uint64_t(off[q + PREFETCH_TAPS]) * step;
            __builtin_prefetch(t);
            __builtin_prefetch(t + row);
        }
        uint32_t o = off[q];
        float* dst = out + q * nc;
        if (o >= TAP_FOLDED) {  // no source, or the folding sampler's
            if (o == TAP_INVALID) {
                for (int64_t ch = 0; ch < nc; ++ch) dst[ch] = 0.0f;
                alpha[q] = 0.0f;
            }
            continue;
        }
        uint64_t p00 = uint64_t(o) * step, p01 = p00 + row;
        alpha[q] = 1.0f;
#if defined(__FMA__)
        if constexpr (NC == 3) {  // the three channels in one vector: lerp's steps, rounded the same
            if (rgb_lerp(flat, p00, p01, tx[q], ty[q], dst)) continue;
        }
#endif
        lerp(flat, p00, p00 + step, p01, p01 + step, tx[q], ty[q], nc, dst);
    }
}

template <int NC>
int bilinear1_t(const float* __restrict__ flat, int64_t sw, int64_t sh, int64_t nc_, const float* __restrict__ xs,
                const float* __restrict__ ys, const bool* __restrict__ valid, int64_t n, Border b,
                float* __restrict__ out, float* __restrict__ alpha, bool zeroed) {
    const int64_t nc = NC > 0 ? NC : nc_;
    uint64_t p[4];
    uint32_t bad = 0;  // a value written is NaN or infinite (all exponent bits set)
    bool covered = false;
    for (int64_t q = 0; q < n; ++q) {
        if (q + PREFETCH < n && valid[q + PREFETCH]) {  // both tap rows of a sample a few ahead (no effect on values)
            const int64_t i = int32_t(xs[q + PREFETCH]), j = int32_t(ys[q + PREFETCH]);
            if (i >= 0 && j >= 0 && i + 1 < sw && j + 1 < sh) {
                const float* t = flat + (j * sw + i) * nc;
                __builtin_prefetch(t);
                __builtin_prefetch(t + sw * nc);
            }
        }
        float* o = out + q * nc;
        if (!valid[q]) {
            if (!zeroed) {  // (zeroed: +0 is there already, and a page only ever read as zeros is never touched)
                for (int64_t ch = 0; ch < nc; ++ch) o[ch] = 0.0f;
                alpha[q] = 0.0f;
            }
            continue;
        }
        float x = clamp_pos(xs[q]), y = clamp_pos(ys[q]);
        float fx0 = ffloor(x), fy0 = ffloor(y);
        corners(int64_t(fx0), int64_t(fy0), sw, sh, nc, b, p);
        lerp(flat, p[0], p[1], p[2], p[3], x - fx0, y - fy0, nc, o);
        for (int64_t ch = 0; ch < nc; ++ch) {  // read back while in a register: no second pass over the output
            uint32_t bits;
            std::memcpy(&bits, o + ch, sizeof bits);
            bad |= uint32_t((bits & 0x7f800000u) == 0x7f800000u);
        }
        alpha[q] = 1.0f;
        covered = true;
    }
    return (bad ? SAMPLED_NON_FINITE : 0) | (covered ? SAMPLED_COVERED : 0);
}

}  // namespace

int bilinear1(const float* flat, int64_t sw, int64_t sh, int64_t nc, const float* xs, const float* ys,
              const bool* valid, int64_t n, Border b, float* out, float* alpha, bool zeroed) {
    switch (nc) {
        case 1: return bilinear1_t<1>(flat, sw, sh, nc, xs, ys, valid, n, b, out, alpha, zeroed);
        case 3: return bilinear1_t<3>(flat, sw, sh, nc, xs, ys, valid, n, b, out, alpha, zeroed);
        case 4: return bilinear1_t<4>(flat, sw, sh, nc, xs, ys, valid, n, b, out, alpha, zeroed);
        default: return bilinear1_t<0>(flat, sw, sh, nc, xs, ys, valid, n, b, out, alpha, zeroed);
    }
}

void bilinear_n(const float* flat, int64_t sw, int64_t sh, int64_t nc, const float* xs, const float* ys,
                const bool* valid, int64_t npix, int64_t ns, Border b, float* out, float* alpha) {
    const float inv = float(1.0 / double(ns));
    uint64_t p[4];
    double acc[64];  // float64 sums: samples of opposite signs near the largest float32 neither overflow nor cancel
    for (int64_t q = 0; q < npix; ++q) {
        for (int64_t ch = 0; ch < nc; ++ch) acc[ch] = 0.0;
        int64_t hits = 0;
        for (int64_t k = q * ns; k < (q + 1) * ns; ++k) {
            if (k + PREFETCH < npix * ns && valid[k + PREFETCH]) {  // a sample a few ahead: both its tap rows
                const int64_t i = int32_t(xs[k + PREFETCH]), j = int32_t(ys[k + PREFETCH]);
                if (i >= 0 && j >= 0 && i + 1 < sw && j + 1 < sh) {
                    const float* t = flat + (j * sw + i) * nc;
                    __builtin_prefetch(t);
                    __builtin_prefetch(t + sw * nc);
                }
            }
            if (!valid[k]) continue;
            ++hits;
            float x = clamp_pos(xs[k]), y = clamp_pos(ys[k]);
            float fx0 = ffloor(x), fy0 = ffloor(y);
            float tx = x - fx0, ty = y - fy0;
            corners(int64_t(fx0), int64_t(fy0), sw, sh, nc, b, p);
            const double w00 = (1.0f - tx) * (1.0f - ty), w10 = tx * (1.0f - ty);  // float32 weights, as before
            const double w01 = (1.0f - tx) * ty, w11 = tx * ty;
            for (int64_t ch = 0; ch < nc; ++ch)
                acc[ch] += w00 * double(flat[p[0] + ch]) + w10 * double(flat[p[1] + ch])
                           + w01 * double(flat[p[2] + ch]) + w11 * double(flat[p[3] + ch]);
        }
        // the mean of finite samples is within float32's range up to a float64 rounding: clamped to it
        for (int64_t ch = 0; ch < nc; ++ch) {
            double v = acc[ch] * double(inv);
            out[q * nc + ch] = float(v > FLT_MAX ? FLT_MAX : (v < -FLT_MAX ? -FLT_MAX : v));
        }
        alpha[q] = float(double(hits) * double(inv));
    }
}

void taps_of(int64_t sw, int64_t sh, const float* xs, const float* ys, const bool* valid, int64_t n,
             uint32_t* off, float* tx, float* ty) {
    for (int64_t q = 0; q < n; ++q) {
        tx[q] = 0.0f;
        ty[q] = 0.0f;
        if (!valid[q]) { off[q] = TAP_INVALID; continue; }
        const float x = clamp_pos(xs[q]), y = clamp_pos(ys[q]);
        float fx0 = ffloor(x), fy0 = ffloor(y);
        int64_t i0 = int64_t(fx0), j0 = int64_t(fy0);
        if (i0 >= 0 && j0 >= 0 && i0 + 1 < sw && j0 + 1 < sh) {
            off[q] = uint32_t(j0 * sw + i0);
            tx[q] = x - fx0;
            ty[q] = y - fy0;
        } else {
            off[q] = TAP_FOLDED;
        }
    }
}


void from_taps(const float* flat, int64_t sw, int64_t nc, const uint32_t* off, const float* tx, const float* ty,
               int64_t n, float* out, float* alpha) {
    switch (nc) {
        case 1: return from_taps_t<1>(flat, sw, nc, off, tx, ty, n, out, alpha);
        case 3: return from_taps_t<3>(flat, sw, nc, off, tx, ty, n, out, alpha);
        case 4: return from_taps_t<4>(flat, sw, nc, off, tx, ty, n, out, alpha);
        default: return from_taps_t<0>(flat, sw, nc, off, tx, ty, n, out, alpha);
    }
}

void folded(const float* flat, int64_t sw, int64_t sh, int64_t nc, const int64_t* idx, const float* xs,
            const float* ys, int64_t m, Border b, float* out, float* alpha) {
    uint64_t p[4];
    for (int64_t e = 0; e < m; ++e) {
        int64_t q = idx[e];
        const float x = clamp_pos(xs[e]), y = clamp_pos(ys[e]);
        float fx0 = ffloor(x), fy0 = ffloor(y);
        corners(int64_t(fx0), int64_t(fy0), sw, sh, nc, b, p);
        lerp(flat, p[0], p[1], p[2], p[3], x - fx0, y - fy0, nc, out + q * nc);
        alpha[q] = 1.0f;
    }
}

void tap_reads(int64_t sw, int64_t sh, const uint32_t* off, int64_t n, const float* xs, const float* ys, int64_t m,
               Border b, uint8_t* read) {
    for (int64_t q = 0; q < n; ++q) {
        if (off[q] >= TAP_FOLDED) continue;
        uint8_t* t = read + off[q];
        t[0] = t[1] = t[sw] = t[sw + 1] = 1;
    }
    uint64_t p[4];
    for (int64_t e = 0; e < m; ++e) {  // the folding sampler's taps, as folded() finds them
        const float x = clamp_pos(xs[e]), y = clamp_pos(ys[e]);
        corners(int64_t(ffloor(x)), int64_t(ffloor(y)), sw, sh, 1, b, p);
        for (int k = 0; k < 4; ++k) read[p[k]] = 1;
    }
}

void read_spans(int64_t sw, int64_t sh, const uint8_t* read, int64_t* spans) {
    for (int64_t j = 0; j < sh; ++j) {
        const uint8_t* r = read + j * sw;
        int64_t* s = spans + 4 * j;
        s[0] = s[1] = s[2] = s[3] = 0;
        int64_t first = 0, last = sw - 1;
        while (first < sw && !r[first]) ++first;
        if (first == sw) continue;  // not read
        while (!r[last]) --last;
        int64_t g0 = 0, g1 = 0;  // the longest run of unread columns between first and last
        for (int64_t c = first; c <= last;) {
            if (r[c]) { ++c; continue; }
            int64_t e = c;
            while (!r[e]) ++e;
            if (e - c > g1 - g0) { g0 = c; g1 = e; }
            c = e;
        }
        s[0] = first;  // first to last, less the longest unread run (none: g0 = g1 = 0, the second span empty)
        s[1] = g1 > g0 ? g0 : last + 1;
        s[2] = g1 > g0 ? g1 : 0;
        s[3] = g1 > g0 ? last + 1 : 0;
    }
}

}  // namespace lenslab
