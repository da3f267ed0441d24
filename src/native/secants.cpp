// Footprint sides of one-sample pixels from their neighbours' map positions (lenslab.warp.antialias):
// central differences, one-sided beside an invalid neighbour, the image's edge or a piece's seam.
#include <cmath>
#include <cstring>
#if defined(__SSE4_1__) || defined(__AVX2__)
#include <immintrin.h>
#endif

#include "sampler.h"

namespace lenslab {

namespace {

// x differences unwrapped by the period `wrap` (> 0; none for 0): a difference across the seam is near +-wrap
inline double unwrap(double dx, double wrap) {
    if (!(wrap > 0.0)) return dx;
#if defined(__SSE4_1__)  // floor in one instruction (the same value as std::floor)
    const double turns = _mm_cvtsd_f64(_mm_round_sd(_mm_setzero_pd(), _mm_set_sd(dx / wrap + 0.5),
                                                    _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC));
#else
    const double turns = std::floor(dx / wrap + 0.5);
#endif
    return dx - wrap * turns;
}

// One pixel (row rr of the map, column c; row r of the output): the general case (an invalid neighbour, the
// image's edge, a piece's seam).
inline void one_pixel(const float* xs, const float* ys, const bool* vs, int64_t nrows, int64_t w, int64_t r,
                      int64_t rr, int64_t c, double wrap, const int32_t* piece, float* foot, bool* edge) {
    const bool v0 = vs[rr * w + c];
    bool on_edge = false;
    for (int axis = 0; axis < 2; ++axis) {
        bool lo_ok, hi_ok;
        int64_t lo, hi;  // flat indices of the neighbours before and after along this axis
        if (axis == 0) {
            lo_ok = c > 0;
            hi_ok = c + 1 < w;
            lo = rr * w + c - 1;
            hi = rr * w + c + 1;
        } else {
            lo_ok = rr > 0;
            hi_ok = rr + 1 < nrows;
            lo = (rr - 1) * w + c;
            hi = (rr + 1) * w + c;
        }
        const int64_t me = rr * w + c;
        if (piece != nullptr) {  // a neighbour in another piece is beyond a seam: it does not count
            lo_ok = lo_ok && piece[lo] == piece[me];
            hi_ok = hi_ok && piece[hi] == piece[me];
        }
        const bool vl = lo_ok && vs[lo], vh = hi_ok && vs[hi];
        if ((lo_ok && vs[lo] != v0) || (hi_ok && vs[hi] != v0)) on_edge = true;
        double half = 1.0, dx = 0.0, dy = 0.0;
        if (vl && vh) {
            dx = double(xs[hi] - xs[lo]);
            dy = double(ys[hi] - ys[lo]);
            half = 0.5;
        } else if (vh && v0) {
            dx = double(xs[hi] - xs[me]);
            dy = double(ys[hi] - ys[me]);
        } else if (vl && v0) {
            dx = double(xs[me] - xs[lo]);
            dy = double(ys[me] - ys[lo]);
        }
        dx = unwrap(dx, wrap);
        foot[(r * w + c) * 4 + 2 * axis] = float(half * dx);
        foot[(r * w + c) * 4 + 2 * axis + 1] = float(half * dy);
    }
    edge[r * w + c] = on_edge;
}

// whether a footprint (a, b) as stored may span more than `far` texels along a side (then it may leave level 0 of
// the pyramid): |a|^2 or |b|^2 beyond far2 (= far^2 less a float32 rounding: a superset of the filter's own test
// in float64), or not a number
inline bool far_side(const float* f, float far2) {
    return !(f[0] * f[0] + f[1] * f[1] <= far2 && f[2] * f[2] + f[3] * f[3] <= far2);
}

#if defined(__AVX2__)
// Eight pixels c .. c + 7 of an inner row whose neighbours all agree with them on validity and are all valid: the
// central differences of one_pixel's fast path, the same operations in the same order, four sides a pixel
// interleaved into foot (32 floats); returns the bit mask of the pixels with a far side (far_side).
inline unsigned central8(const float* xs, const float* ys, int64_t me, int64_t w, double wrap, float far2, float* f) {
    const __m256 xl = _mm256_loadu_ps(xs + me - 1), xr = _mm256_loadu_ps(xs + me + 1);
    const __m256 xu = _mm256_loadu_ps(xs + me - w), xd = _mm256_loadu_ps(xs + me + w);
    const __m256 yl = _mm256_loadu_ps(ys + me - 1), yr = _mm256_loadu_ps(ys + me + 1);
    const __m256 yu = _mm256_loadu_ps(ys + me - w), yd = _mm256_loadu_ps(ys + me + w);
    const __m256d half = _mm256_set1_pd(0.5);
    auto halved = [&](__m256 d) {  // float(0.5 * unwrap(double(d))), eight at a time
        __m256d lo = _mm256_cvtps_pd(_mm256_castps256_ps128(d)), hi = _mm256_cvtps_pd(_mm256_extractf128_ps(d, 1));
        if (wrap > 0.0) {
            const __m256d p = _mm256_set1_pd(wrap), h = _mm256_set1_pd(0.5);
            // dx - wrap * turns: turns is a whole number, so wrap * turns is exact for any whole period below 2^26
            // and fusing the multiply-add (as the scalar path may) changes nothing
            lo = _mm256_sub_pd(lo, _mm256_mul_pd(p, _mm256_floor_pd(_mm256_add_pd(_mm256_div_pd(lo, p), h))));
            hi = _mm256_sub_pd(hi, _mm256_mul_pd(p, _mm256_floor_pd(_mm256_add_pd(_mm256_div_pd(hi, p), h))));
        }
        return _mm256_set_m128(_mm256_cvtpd_ps(_mm256_mul_pd(half, hi)), _mm256_cvtpd_ps(_mm256_mul_pd(half, lo)));
    };
    const __m256 hf = _mm256_set1_ps(0.5f);  // y: float(0.5 * double(d)) is 0.5f * d (both the exact half, rounded once)
    const __m256 ax = halved(_mm256_sub_ps(xr, xl)), ay = _mm256_mul_ps(hf, _mm256_sub_ps(yr, yl));
    const __m256 bx = halved(_mm256_sub_ps(xd, xu)), by = _mm256_mul_ps(hf, _mm256_sub_ps(yd, yu));
    // (ax, ay, bx, by) of each pixel, pixel after pixel
    const __m256 t0 = _mm256_unpacklo_ps(ax, ay), t1 = _mm256_unpackhi_ps(ax, ay);
    const __m256 t2 = _mm256_unpacklo_ps(bx, by), t3 = _mm256_unpackhi_ps(bx, by);
    const __m256 u0 = _mm256_shuffle_ps(t0, t2, 0x44), u1 = _mm256_shuffle_ps(t0, t2, 0xEE);
    const __m256 u2 = _mm256_shuffle_ps(t1, t3, 0x44), u3 = _mm256_shuffle_ps(t1, t3, 0xEE);
    _mm256_storeu_ps(f, _mm256_permute2f128_ps(u0, u1, 0x20));
    _mm256_storeu_ps(f + 8, _mm256_permute2f128_ps(u2, u3, 0x20));
    _mm256_storeu_ps(f + 16, _mm256_permute2f128_ps(u0, u1, 0x31));
    _mm256_storeu_ps(f + 24, _mm256_permute2f128_ps(u2, u3, 0x31));
    const __m256 lim = _mm256_set1_ps(far2);
    const __m256 la = _mm256_add_ps(_mm256_mul_ps(ax, ax), _mm256_mul_ps(ay, ay));
    const __m256 lb = _mm256_add_ps(_mm256_mul_ps(bx, bx), _mm256_mul_ps(by, by));
    const __m256 near = _mm256_and_ps(_mm256_cmp_ps(la, lim, _CMP_LE_OQ), _mm256_cmp_ps(lb, lim, _CMP_LE_OQ));
    return unsigned(~_mm256_movemask_ps(near)) & 0xFFu;
}
#endif

}  // namespace

int64_t neighbour_secants(const float* xs, const float* ys, const bool* vs, int64_t nrows, int64_t w, int64_t top,
                          int64_t h, double wrap, const int32_t* piece, float* foot, bool* edge, double far,
                          int64_t* coarse) {
    // far^2, less 1e-6 of it (a float32 |a|^2 is within 2^-22 of the float64 one): never misses a far footprint
    const float far2 = float(far * far * (1.0 - 1e-6));
    int64_t count = 0;
    auto note = [&](int64_t q, const float* f) {
        if (coarse != nullptr && far_side(f, far2)) coarse[count++] = q;
    };
    for (int64_t r = 0; r < h; ++r) {
        const int64_t rr = r + top;
        const bool inner = piece == nullptr && rr > 0 && rr + 1 < nrows;
        for (int64_t c = 0; c < w; ++c) {
            const int64_t me = rr * w + c;
#if defined(__AVX2__)
            // eight pixels whose neighbours all agree with them and with each other: the validity bytes of the
            // pixels and of their four neighbours, compared eight at a time
            if (inner && c > 0 && c + 8 < w) {
                uint64_t v0, vl, vr, vu, vd;
                std::memcpy(&v0, vs + me, 8);
                std::memcpy(&vl, vs + me - 1, 8);
                std::memcpy(&vr, vs + me + 1, 8);
                std::memcpy(&vu, vs + me - w, 8);
                std::memcpy(&vd, vs + me + w, 8);
                if (v0 == vl && v0 == vr && v0 == vu && v0 == vd && (v0 == 0 || v0 == 0x0101010101010101ull)) {
                    float* f = foot + (r * w + c) * 4;
                    std::memset(edge + r * w + c, 0, 8);
                    if (v0 == 0) {
                        std::memset(f, 0, 32 * sizeof(float));
                    } else {
                        unsigned far_bits = central8(xs, ys, me, w, wrap, far2, f);
                        while (coarse != nullptr && far_bits) {
                            coarse[count++] = r * w + c + __builtin_ctz(far_bits);
                            far_bits &= far_bits - 1;
                        }
                    }
                    c += 7;
                    continue;
                }
            }
#endif
            // a pixel inside one piece with its four neighbours all valid or all invalid (nearly every one):
            // central differences, or zero sides; no edge
            if (inner && c > 0 && c + 1 < w) {
                const bool v0 = vs[me];
                const bool same = vs[me - 1] == v0 && vs[me + 1] == v0 && vs[me - w] == v0 && vs[me + w] == v0;
                if (same) {
                    float* f = foot + (r * w + c) * 4;
                    if (v0) {
                        f[0] = float(0.5 * unwrap(double(xs[me + 1] - xs[me - 1]), wrap));
                        f[1] = float(0.5 * double(ys[me + 1] - ys[me - 1]));
                        f[2] = float(0.5 * unwrap(double(xs[me + w] - xs[me - w]), wrap));
                        f[3] = float(0.5 * double(ys[me + w] - ys[me - w]));
                        note(r * w + c, f);
                    } else {
                        f[0] = f[1] = f[2] = f[3] = 0.0f;
                    }
                    edge[r * w + c] = false;
                    continue;
                }
            }
            one_pixel(xs, ys, vs, nrows, w, r, rr, c, wrap, piece, foot, edge);
            if (vs[me]) note(r * w + c, foot + (r * w + c) * 4);
        }
    }
    return count;
}

}  // namespace lenslab

// Footprint sides of supersampled pixels (lenslab.warp.antialias.secants): xs, ys, vs (h, w, 5, n), the map at
// each sample (index 0) and at the ends of its two secants (1, 2 along x; 3, 4 along y); foot (h, w, n, 4).
// Each side is the secant across the sample's stratum, one-sided (doubled) where an end is invalid, 0 where
// both are; x differences are unwrapped by the period `wrap` (> 0).
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <stdexcept>

namespace lenslab {

void secants(const float* xs, const float* ys, const bool* vs, int64_t npix, int64_t n, double wrap, float* foot) {
    for (int64_t p = 0; p < npix; ++p) {
        const int64_t base = p * 5 * n;
        for (int64_t k = 0; k < n; ++k) {
            const int64_t c0 = base + k;
            for (int axis = 0; axis < 2; ++axis) {
                const int64_t lo = base + (1 + 2 * axis) * n + k, hi = base + (2 + 2 * axis) * n + k;
                double dx = 0.0, dy = 0.0;
                if (vs[lo] && vs[hi]) {
                    dx = double(xs[hi] - xs[lo]);
                    dy = double(ys[hi] - ys[lo]);
                } else if (vs[hi] && vs[c0]) {
                    dx = 2.0 * double(xs[hi] - xs[c0]);
                    dy = 2.0 * double(ys[hi] - ys[c0]);
                } else if (vs[lo] && vs[c0]) {
                    dx = 2.0 * double(xs[c0] - xs[lo]);
                    dy = 2.0 * double(ys[c0] - ys[lo]);
                }
                if (wrap > 0.0) dx -= wrap * std::floor(dx / wrap + 0.5);
                foot[(p * n + k) * 4 + 2 * axis] = float(dx);
                foot[(p * n + k) * 4 + 2 * axis + 1] = float(dy);
            }
        }
    }
}

}  // namespace lenslab

namespace nb = nanobind;

// The binding (lenslab.cxx_kernels.secants), registered by src/native/module.cpp; the GIL is released.
void register_secants(nb::module_& m) {
    using InF = nb::ndarray<const float, nb::c_contig, nb::device::cpu>;
    using InB = nb::ndarray<const bool, nb::c_contig, nb::device::cpu>;
    using OutF = nb::ndarray<float, nb::c_contig, nb::device::cpu>;
    m.def("secants", [](InF xs, InF ys, InB vs_, double wrap, OutF foot) {
        if (xs.ndim() != 4 || xs.shape(2) != 5 || ys.size() != xs.size() || vs_.size() != xs.size())
            throw std::invalid_argument("secants: xs, ys, vs must be (h, w, 5, n) alike");
        const int64_t n = int64_t(xs.shape(3)), npix = int64_t(xs.shape(0) * xs.shape(1));
        if (foot.size() != size_t(npix * n * 4)) throw std::invalid_argument("secants: foot must be (h, w, n, 4)");
        nb::gil_scoped_release release;
        lenslab::secants(xs.data(), ys.data(), vs_.data(), npix, n, wrap, foot.data());
    }, nb::arg("xs"), nb::arg("ys"), nb::arg("vs"), nb::arg("wrap"), nb::arg("foot").noconvert());
}
