// The footprint filter's source side (lenslab.warp.pyramid): the 2x2 box means that make each pyramid level from
// the one before (`halve`) and the rows of each level that a band's footprints read (`level_rows`). NumPy
// references: lenslab.warp.kernels.reference.halve and level_rows.
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <optional>
#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>

#include "bind.h"
#include "footprint_edges.h"

namespace lenslab {
namespace {

using footprint_edges::bfloor;
using footprint_edges::clamp_side;
using footprint_edges::ifloor;
using footprint_edges::WINDOW;

// one texel channel of a level: the mean of its 2x2 block, summed in float64 in this order (the bits of every
// path below and of the reference)
inline float mean4(const float* r0, const float* r1, int64_t k, int64_t nc) {
    return float(((double(r0[k]) + double(r0[k + nc])) + (double(r1[k]) + double(r1[k + nc]))) * 0.25);
}

void halve_scalar(const float* r0, const float* r1, int64_t i0, int64_t i1, int64_t nc, float* o) {
    for (int64_t i = i0; i < i1; ++i)
        for (int64_t ch = 0; ch < nc; ++ch) o[i * nc + ch] = mean4(r0, r1, 2 * i * nc + ch, nc);
}

#if defined(__AVX2__)
// four doubles of the 2x2 sums at float offsets k and k + nc of both rows, in mean4's order, as four floats
inline __m128 mean4_v(const float* r0, const float* r1, int64_t k, int64_t nc) {
    const __m256d a = _mm256_cvtps_pd(_mm_loadu_ps(r0 + k)), b = _mm256_cvtps_pd(_mm_loadu_ps(r0 + k + nc));
    const __m256d c = _mm256_cvtps_pd(_mm_loadu_ps(r1 + k)), d = _mm256_cvtps_pd(_mm_loadu_ps(r1 + k + nc));
    return _mm256_cvtpd_ps(_mm256_mul_pd(_mm256_add_pd(_mm256_add_pd(a, b), _mm256_add_pd(c, d)), _mm256_set1_pd(0.25)));
}

// the row's 2x2 sums of horizontal neighbours, in doubles: pixels 2i .. 2i + 7 of one channel -> four sums
inline __m256d pair_sums1(const float* r) {
    const __m256d lo = _mm256_cvtps_pd(_mm_loadu_ps(r)), hi = _mm256_cvtps_pd(_mm_loadu_ps(r + 4));
    // hadd: (r0 + r1, r4 + r5, r2 + r3, r6 + r7), then in order
    return _mm256_permute4x64_pd(_mm256_hadd_pd(lo, hi), 0xD8);
}

// two channels: pixels 2i .. 2i + 3 (eight floats) -> the sums of two output pixels
inline __m256d pair_sums2(const float* r) {
    const __m256d lo = _mm256_cvtps_pd(_mm_loadu_ps(r)), hi = _mm256_cvtps_pd(_mm_loadu_ps(r + 4));
    return _mm256_add_pd(_mm256_permute2f128_pd(lo, hi, 0x20), _mm256_permute2f128_pd(lo, hi, 0x31));
}
#endif

// One output row: o (ow, nc) from the source rows r0, r1 (2 ow, nc).
void halve_row(const float* r0, const float* r1, int64_t ow, int64_t nc, float* o) {
#if defined(__AVX2__)
    const __m256d q = _mm256_set1_pd(0.25);
    if (nc == 1) {
        int64_t i = 0;
        for (; i + 4 <= ow; i += 4)
            _mm_storeu_ps(o + i, _mm256_cvtpd_ps(_mm256_mul_pd(_mm256_add_pd(pair_sums1(r0 + 2 * i), pair_sums1(r1 + 2 * i)), q)));
        return halve_scalar(r0, r1, i, ow, nc, o);
    }
    if (nc == 2) {
        int64_t i = 0;
        for (; i + 2 <= ow; i += 2)
            _mm_storeu_ps(o + 2 * i, _mm256_cvtpd_ps(_mm256_mul_pd(_mm256_add_pd(pair_sums2(r0 + 4 * i), pair_sums2(r1 + 4 * i)), q)));
        return halve_scalar(r0, r1, i, ow, nc, o);
    }
    if (nc == 3) {  // four lanes a pixel: the fourth is the next pixel's first channel, written again after
        int64_t i = 0;  // (the last pixel of the row, whose fourth lane lies beyond the rows, is scalar)
        for (; i + 1 < ow; ++i) _mm_storeu_ps(o + 3 * i, mean4_v(r0, r1, 6 * i, 3));
        return halve_scalar(r0, r1, i, ow, nc, o);
    }
    for (int64_t i = 0; i < ow; ++i)  // groups of four channels, the last group ending at the last channel
        for (int64_t c0 = 0; c0 < nc; c0 += 4) {
            const int64_t c = std::min(c0, nc - 4);
            _mm_storeu_ps(o + i * nc + c, mean4_v(r0, r1, 2 * i * nc + c, nc));
        }
#else
    halve_scalar(r0, r1, 0, ow, nc, o);
#endif
}

}  // namespace

// One pyramid level: out (h/2, w/2, nc) = the mean of each 2x2 block of src (h, w, nc), summed in float64 (a mean
// of finite float32 values is finite).
void halve(const float* src, int64_t h, int64_t w, int64_t nc, float* out) {
    const int64_t oh = h / 2, ow = w / 2, row = w * nc;
    for (int64_t j = 0; j < oh; ++j) halve_row(src + 2 * j * row, src + (2 * j + 1) * row, ow, nc, out + j * ow * nc);
}

// The rows of each pyramid level (levels 1..) that the footprint filter reads for these samples: rows (nlev, 2)
// int64, [first, end) widened to cover every sample whose footprint picks that level (its window, a texel more
// each way; a level no sample picks keeps first > end). Rows beyond the image are left for the caller to fold.
// idx (m, or null: every sample): the samples to look at (the others' footprints are known to pick level 0).
void level_rows(const int64_t* shapes, int64_t nlev, const float* ys, const bool* valid, const float* foot,
                int64_t n, const int64_t* idx, int64_t m, double max_taps, int64_t* rows) {
    const double h0 = double(shapes[0]);
    const int64_t count = idx != nullptr ? m : n;
    for (int64_t e = 0; e < count; ++e) {
        const int64_t s = idx != nullptr ? idx[e] : e;
        if (!valid[s]) continue;
        const float* f = foot + 4 * s;
        const double ax = clamp_side(f[0]), ay = clamp_side(f[1]), bx = clamp_side(f[2]), by = clamp_side(f[3]);
        const double la = ax * ax + ay * ay, lb = bx * bx + by * by;
        if (!(std::max(la, lb) > max_taps * max_taps)) continue;  // level 0 (no square root for most)
        const double longest = std::max(std::sqrt(la), std::sqrt(lb));
        if (!(longest > max_taps)) continue;
        int64_t lev = 0;
        while (lev + 1 < nlev && longest > max_taps * double(int64_t(1) << lev)) ++lev;
        const int64_t lh = shapes[2 * lev];
        const double scale = double(lh) / h0;
        const double ey = std::min(0.5 * (std::fabs(ay) + std::fabs(by)) * scale + 1.0, double(WINDOW / 2 + 1));
        const double cy = (double(clamp_pos(ys[s])) + 0.5) * scale - 0.5;
        const int64_t lo = std::max(-lh, ifloor(cy - ey) - 1), hi = std::min(2 * lh, ifloor(cy + ey) + 2);
        rows[2 * lev] = std::min(rows[2 * lev], lo);
        rows[2 * lev + 1] = std::max(rows[2 * lev + 1], hi);
    }
}

}  // namespace lenslab

// The bindings (lenslab.cxx_kernels.halve, level_rows), registered by src/native/module.cpp; the GIL is released.
namespace nb = nanobind;

void register_pyramid(nb::module_& m) {
    using namespace lenslab;
    using namespace lenslab::bind;

    m.def("level_rows", [](InI shapes, InF ys, InB valid, InF foot, double max_taps, bind::Out<int64_t> rows,
                           std::optional<InI> idx) {
        need(shapes.ndim() == 2 && shapes.shape(1) == 2 && shapes.shape(0) > 0, "pyramid shapes");
        need(valid.size() == ys.size() && foot.size() == 4 * ys.size(), "level_rows: ys, valid, foot (n, 4) alike");
        need(rows.size() == 2 * shapes.shape(0), "level_rows: rows must be (levels, 2)");
        need(max_taps > 0.0, "max_taps must be positive");
        const int64_t n = int64_t(ys.size());
        const int64_t* ip = idx ? idx->data() : nullptr;
        const int64_t m_ = idx ? int64_t(idx->size()) : 0;
        for (int64_t e = 0; e < m_; ++e) need(ip[e] >= 0 && ip[e] < n, "level_rows: a sample index out of range");
        int64_t* r = rows.data();
        for (size_t l = 0; l < shapes.shape(0); ++l) { r[2 * l] = INT64_MAX; r[2 * l + 1] = INT64_MIN; }
        nb::gil_scoped_release release;
        level_rows(shapes.data(), int64_t(shapes.shape(0)), ys.data(), valid.data(), foot.data(), n, ip, m_, max_taps, r);
    }, nb::arg("shapes"), nb::arg("ys"), nb::arg("valid"), nb::arg("foot"), nb::arg("max_taps"),
       nb::arg("rows").noconvert(), nb::arg("idx") = nb::none());

    m.def("halve", [](InF src, bind::Out<float> out) {
        need(src.ndim() == 3 && out.ndim() == 3 && out.shape(0) == src.shape(0) / 2 && out.shape(1) == src.shape(1) / 2
             && out.shape(2) == src.shape(2), "halve: out must be (h/2, w/2, c) of src (h, w, c)");
        nb::gil_scoped_release release;
        halve(src.data(), int64_t(src.shape(0)), int64_t(src.shape(1)), int64_t(src.shape(2)), out.data());
    }, nb::arg("src"), nb::arg("out").noconvert());
}
