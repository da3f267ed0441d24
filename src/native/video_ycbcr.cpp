// Y'CbCr passes of video frames (lenslab.cxx_kernels, registered by register_video_ycbcr), exact to the matrix and
// range formulas (ITU-R BT.709 / BT.601 / BT.2020, ITU-T H.273), each without the GIL on `threads` threads:
// - ycbcr_to_linear: a decoder's planes (8 to 16 bits, 4:2:0 / 4:2:2 / 4:4:4, chroma upsampled by repetition) ->
//   R'G'B' in float32 -> clamped to [0, 1] -> the transfer function's 65536-entry table, interpolated linearly ->
//   linear light (float32), a window of the frame only;
// - linear_to_ycbcr: linear float32 -> the inverse transfer function's table (lenslab.io.video_colour) -> R'G'B'
//   in [0, 1] -> Y'CbCr -> codes rounded once, chroma the mean of each block's Cb and Cr.
// NumPy references: lenslab/io/video_ycbcr.py (the tests compare them).
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include "video_common.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <thread>
#include <vector>

namespace nb = nanobind;
using lenslab_video::bands;
using lenslab_video::Curve;
using lenslab_video::need;

namespace {

using Plane = nb::ndarray<nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using lenslab::bind::In;
using lenslab::bind::Out;

// How codes stand for values: Y' = (code - y0) / ys, C = (code - c0) / cs (a division: 940 is 1 exactly)
struct Range {
    double y0, ys, c0, cs;
};

// The planes of one frame: sample pointers and row strides (in samples), chroma shifts
template <typename T> struct Planes {
    T* y;
    T* u;
    T* v;
    int64_t sy_, su, sv;
    int hx, vy;  // log2 of the chroma subsampling across and down
};

// The transfer function at x = 65535 E' from `t`, 65536 pairs (value at code i, step to code i + 1; the last
// step 0), E' clamped to [0, 1], interpolated linearly in float32
inline float lookup(const float* t, float x) {
    x = x > 0.0f ? (x < 65535.0f ? x : 65535.0f) : 0.0f;
    int32_t i = int32_t(x);
    return t[2 * i] + (x - float(i)) * t[2 * i + 1];
}

// n pixels (n x 3, float32) through the 3 x 3 matrix `mf` (row-major) in place
inline void primaries(float* o, int64_t n, const float* mf) {
    for (int64_t c = 0; c < n; ++c) {
        float e0 = o[3 * c], e1 = o[3 * c + 1], e2 = o[3 * c + 2];
        for (int q = 0; q < 3; ++q) o[3 * c + q] = mf[3 * q] * e0 + mf[3 * q + 1] * e1 + mf[3 * q + 2] * e2;
    }
}

// The codes' values times 65535 (tables rounded once from float64, so white is 65535 exactly): Y' (ly) and chroma
// (lc), n codes each
inline void code_values(Range r, int64_t n, float* ly, float* lc) {
    for (int64_t c = 0; c < n; ++c) {
        ly[c] = float((double(c) - r.y0) / r.ys * 65535.0);
        lc[c] = float((double(c) - r.c0) / r.cs * 65535.0);
    }
}

// 8-bit samples, a matrix whose R' row has no Cb and B' row no Cr (BT.709, BT.601, BT.2020): R' depends on Y' and Cr
// only, B' on Y' and Cb, so their linear values are two tables of 256 x 256 (`rb`: R' by Cr then Y', then B' by Cb
// then Y'), made by the lookups to_linear makes, leaving one lookup a pixel (G')
void rb_tables(Range r, const double* k, const float* t, float* rb) {
    float ly[256], lc[256];
    code_values(r, 256, ly, lc);
    const float kb0 = float(k[1]), kr0 = float(k[2]), kb2 = float(k[7]), kr2 = float(k[8]);
    for (int64_t c = 0; c < 256; ++c) {
        const float cr = kb0 * 0.0f + kr0 * lc[c], cb = kb2 * lc[c] + kr2 * 0.0f;
        for (int64_t y = 0; y < 256; ++y) {
            rb[c * 256 + y] = lookup(t, ly[y] + cr);
            rb[65536 + c * 256 + y] = lookup(t, ly[y] + cb);
        }
    }
}

#include "video_decode_x8.h"  // rgb8_row_x8: the decoding's 8-bit rows eight pixels at a time (AVX2)

// Y'CbCr planes -> linear float32 in the window [r0, r1) x [c0, c1) of `out` (rows x cols x 3), in float32. With
// `k` the Y'CbCr -> R'G'B' matrix (its first column is 1): 65535 E'q = LY[Y] + (k[q][1] LC[Cb] + k[q][2] LC[Cr]),
// LY and LC the codes' values (code_values), the bracket once per chroma sample; then the transfer function's
// table, then `m` (BT.2020 -> Rec.709) when given. `rb` (8-bit samples; may be null): R' and B' from rb_tables.
template <typename T>
void to_linear(Planes<const T> p, Range r, const double* k, const float* t, const float* rb, const double* m,
               float* out, int64_t cols, int64_t r0, int64_t r1, int64_t c0_, int64_t c1_, const int64_t* spans,
               int64_t threads) {
    constexpr int64_t N = int64_t(1) << (8 * sizeof(T));
    std::vector<float> ly(N), lc(N);
    code_values(r, N, ly.data(), lc.data());
    const float kb[3] = {float(k[1]), float(k[4]), float(k[7])}, kr[3] = {float(k[2]), float(k[5]), float(k[8])};
    float mf[9];
    for (int q = 0; q < 9; ++q) mf[q] = m ? float(m[q]) : 0.0f;
    const float* LY = ly.data();
    const float* LC = lc.data();
    const float* TR = N == 256 ? rb : nullptr;
    const float* TB = TR == nullptr ? nullptr : TR + 65536;
    bands(r1 - r0, threads, 1, [=](int64_t b0, int64_t b1) {
        std::vector<float> chroma(size_t(std::max<int64_t>(((c1_ - 1) >> p.hx) + 1 - (c0_ >> p.hx), 0)) * 3),
            xs(size_t(std::max<int64_t>((c1_ - c0_) * 3, 0)));
        for (int64_t piece = int64_t(r0 + b0) * 2; piece < int64_t(r0 + b1) * 2; ++piece) {
            // row j's columns c0 to c1 - 1: the window's, or (spans) narrowed to each of the row's two spans
            const int64_t j = piece >> 1, e = piece & 1;
            if (spans == nullptr && e) continue;
            const int64_t c0 = spans ? std::max(c0_, spans[4 * j + 2 * e]) : c0_;
            const int64_t c1 = spans ? std::min(c1_, spans[4 * j + 2 * e + 1]) : c1_;
            if (c1 <= c0) continue;
            const int64_t k0 = c0 >> p.hx, k1 = ((c1 - 1) >> p.hx) + 1, n = (c1 - c0) * 3;
            const T* yr = p.y + j * p.sy_;
            const T* ur = p.u + (j >> p.vy) * p.su;
            const T* vr = p.v + (j >> p.vy) * p.sv;
            float* ch = chroma.data() - 3 * k0;
            if (TR != nullptr) {  // R' and B' from their tables, G' by its lookup
                float* g = chroma.data() - k0;
                for (int64_t cc = k0; cc < k1; ++cc) g[cc] = kb[1] * LC[ur[cc]] + kr[1] * LC[vr[cc]];
                float* o = out + j * cols * 3;
                // eight pixels at a time where the CPU can, the rest one by one
                for (int64_t c = rgb8_row_x8(reinterpret_cast<const uint8_t*>(yr),
                                             reinterpret_cast<const uint8_t*>(ur),
                                             reinterpret_cast<const uint8_t*>(vr), p.hx, g, LY, t, TR, TB, c0, c1, k1,
                                             o);
                     c < c1; ++c) {
                    const int64_t y = yr[c], cc = c >> p.hx;
                    o[3 * c] = TR[(int64_t(vr[cc]) << 8) + y];
                    o[3 * c + 1] = lookup(t, LY[y] + g[cc]);
                    o[3 * c + 2] = TB[(int64_t(ur[cc]) << 8) + y];
                }
                if (m != nullptr) primaries(o + c0 * 3, c1 - c0, mf);
                continue;
            }
            for (int64_t cc = k0; cc < k1; ++cc) {
                float cb = LC[ur[cc]], cr = LC[vr[cc]];
                for (int q = 0; q < 3; ++q) ch[3 * cc + q] = kb[q] * cb + kr[q] * cr;
            }
            float* x = xs.data() - 3 * c0;
            for (int64_t c = c0; c < c1; ++c) {
                float yy = LY[yr[c]];
                const float* g = ch + 3 * (c >> p.hx);
                for (int q = 0; q < 3; ++q) x[3 * c + q] = yy + g[q];
            }
            // one plain loop over the row's values, which the compiler turns into vector gathers
            float* o = out + (j * cols + c0) * 3;
            const float* xv = xs.data();
            for (int64_t q = 0; q < n; ++q) o[q] = lookup(t, xv[q]);
            if (m != nullptr) primaries(o, c1 - c0, mf);
        }
    });
}

// One row of linear float32 (cols x 3) -> R'G'B' in [0, 1] in `e`: NaN and infinities made finite, `m` (Rec.709 ->
// the stream's primaries) when given, the inverse transfer function's table (none: values already encoded), clamped.
inline void encoded_row(const float* a, int64_t cols, const double* m, const Curve& curve, float* e) {
    const int64_t n = cols * 3;
    for (int64_t q = 0; q < n; ++q) e[q] = lenslab_video::finite(a[q]);
    if (m != nullptr) {
        for (int64_t c = 0; c < cols; ++c) {
            float y0 = e[3 * c], y1 = e[3 * c + 1], y2 = e[3 * c + 2];
            for (int q = 0; q < 3; ++q) e[3 * c + q] = float(m[3 * q] * y0 + m[3 * q + 1] * y1 + m[3 * q + 2] * y2);
        }
    }
    // plain loops over the row's values, which the compiler turns into vector gathers and clamps
    if (curve.table != nullptr) {
        lenslab_video::curve_many(curve, e, e, n);
    }
    for (int64_t q = 0; q < n; ++q) e[q] = e[q] > 0.0f ? (e[q] < 1.0f ? e[q] : 1.0f) : 0.0f;
}

#include "video_codes_x8.h"  // row_codes_x8: the encoding's rows eight pixels at a time (AVX2)

// Linear float32 -> Y'CbCr planes: per row, R'G'B' (encoded_row), then Y' in float64 rounded once to its code, and
// each pixel's E'cb and E'cr (float64) kept for its chroma block; a block's chroma is their mean, summed row by row
// in column order, rounded once. HX, VY: log2 of the chroma subsampling, known to the compiler, so that the loops
// over a row (stride-3 reads, one code per pixel) vectorise.
template <typename T, int HX, int VY>
void from_linear_t(const float* lin, int64_t rows, int64_t cols, const double* m, Curve curve, const double* k,
                   Range r, double top, Planes<T> p, int64_t threads) {
    constexpr int64_t bw = int64_t(1) << HX, bh = int64_t(1) << VY;
    const int64_t ccols = (cols + bw - 1) / bw, full = cols / bw;
    const double k0 = k[0], k1 = k[1], k2 = k[2], k3 = k[3], k4 = k[4], k5 = k[5], k6 = k[6], k7 = k[7], k8 = k[8];
    auto code = [top](double x) { return T(std::nearbyint(x > 0.0 ? (x < top ? x : top) : 0.0)); };
    bands(rows, threads, bh, [=](int64_t j0, int64_t j1) {
        std::vector<float> es(size_t(cols) * 3);
        std::vector<double> us(size_t(bh * cols)), vs(size_t(bh * cols));
        float* e = es.data();
        for (int64_t jb = j0; jb < j1; jb += bh) {
            const int64_t je = std::min(j1, jb + bh);
            for (int64_t j = jb; j < je; ++j) {
                const float* a = lin + j * cols * 3;
                T* yr = p.y + j * p.sy_;
                double* u = us.data() + (j - jb) * cols;
                double* v = vs.data() + (j - jb) * cols;
                // eight pixels at a time where the CPU can (no primaries to convert: the curve makes NaN and
                // infinities finite as finite() would, 0 and the last knot), the rest one by one
                const int64_t done = m == nullptr ? row_codes_x8(a, cols, curve, k, r, top, yr, u, v) : 0;
                encoded_row(a + done * 3, cols - done, m, curve, e);
                for (int64_t c = done; c < cols; ++c) {
                    const float* ec = e + 3 * (c - done);
                    const double e0 = ec[0], e1 = ec[1], e2 = ec[2];
                    yr[c] = code((k0 * e0 + k1 * e1 + k2 * e2) * r.ys + r.y0);
                    u[c] = k3 * e0 + k4 * e1 + k5 * e2;
                    v[c] = k6 * e0 + k7 * e1 + k8 * e2;
                }
            }
            const int64_t nr = je - jb;
            T* ur = p.u + (jb >> VY) * p.su;
            T* vr = p.v + (jb >> VY) * p.sv;
            const double* u = us.data();
            const double* v = vs.data();
            if (nr == bh) {  // whole blocks: the sums unrolled
                const double nb = double(bw * bh);
                for (int64_t cc = 0; cc < full; ++cc) {
                    double su = 0.0, sv = 0.0;
                    for (int64_t jj = 0; jj < bh; ++jj) {
                        for (int64_t x = 0; x < bw; ++x) {
                            su += u[jj * cols + cc * bw + x];
                            sv += v[jj * cols + cc * bw + x];
                        }
                    }
                    ur[cc] = code(su / nb * r.cs + r.c0);
                    vr[cc] = code(sv / nb * r.cs + r.c0);
                }
            }
            for (int64_t cc = nr == bh ? full : 0; cc < ccols; ++cc) {  // blocks cut by the frame's edges
                const int64_t x1 = std::min(cols, (cc + 1) * bw);
                double su = 0.0, sv = 0.0;
                for (int64_t jj = 0; jj < nr; ++jj) {
                    for (int64_t x = cc * bw; x < x1; ++x) {
                        su += u[jj * cols + x];
                        sv += v[jj * cols + x];
                    }
                }
                const double nb = double(nr * (x1 - cc * bw));
                ur[cc] = code(su / nb * r.cs + r.c0);
                vr[cc] = code(sv / nb * r.cs + r.c0);
            }
        }
    });
}

template <typename T>
void from_linear(const float* lin, int64_t rows, int64_t cols, const double* m, Curve curve, const double* k, Range r,
                 double top, Planes<T> p, int64_t threads) {
    switch (p.hx * 2 + p.vy) {
        case 0: return from_linear_t<T, 0, 0>(lin, rows, cols, m, curve, k, r, top, p, threads);
        case 1: return from_linear_t<T, 0, 1>(lin, rows, cols, m, curve, k, r, top, p, threads);
        case 2: return from_linear_t<T, 1, 0>(lin, rows, cols, m, curve, k, r, top, p, threads);
        default: return from_linear_t<T, 1, 1>(lin, rows, cols, m, curve, k, r, top, p, threads);
    }
}

template <typename T> Planes<T> planes_of(Plane& y, Plane& u, Plane& v, int hx, int vy) {
    return Planes<T>{static_cast<T*>(y.data()), static_cast<T*>(u.data()), static_cast<T*>(v.data()),
                     int64_t(y.shape(1)), int64_t(u.shape(1)), int64_t(v.shape(1)), hx, vy};
}

void check_planes(Plane& y, Plane& u, Plane& v, int64_t h, int64_t w, int hx, int vy) {
    need(y.dtype() == u.dtype() && y.dtype() == v.dtype(), "planes of one sample type");
    need(y.dtype() == nb::dtype<uint8_t>() || y.dtype() == nb::dtype<uint16_t>(), "planes of uint8 or uint16");
    need(0 <= hx && hx <= 1 && 0 <= vy && vy <= 1, "chroma subsampling of 1 or 2");
    need(int64_t(y.shape(0)) >= h && int64_t(y.shape(1)) >= w, "the luma plane is smaller than the frame");
    int64_t ch = (h + (1 << vy) - 1) >> vy, cw = (w + (1 << hx) - 1) >> hx;
    need(int64_t(u.shape(0)) >= ch && int64_t(u.shape(1)) >= cw && int64_t(v.shape(0)) >= ch &&
             int64_t(v.shape(1)) >= cw, "a chroma plane is smaller than the frame");
}

}  // namespace

void register_video_ycbcr(nb::module_& m) {
    m.def("ycbcr_rb_tables", [](In<double> range, In<double> matrix, In<float> table, Out<float> out) {
        need(range.size() == 4 && matrix.size() == 9 && table.size() == 2 * 65536, "range 4, matrix 9, table 2 x 65536");
        need(out.size() == 2 * 65536, "out: 2 x 256 x 256");
        const double* k = matrix.data();
        need(k[1] == 0.0 && k[8] == 0.0, "a matrix whose R' row has no Cb and B' row no Cr");
        const double* g = range.data();
        rb_tables(Range{g[0], g[1], g[2], g[3]}, k, table.data(), out.data());
    }, nb::arg("range"), nb::arg("matrix"), nb::arg("table"), nb::arg("out").noconvert(),
       nb::call_guard<nb::gil_scoped_release>());

    m.def("ycbcr_to_linear", [](Plane y, Plane u, Plane v, int hx, int vy, In<double> range, In<double> matrix,
                                In<float> table, In<float> rb, In<double> primaries, Out<float> out, int64_t r0,
                                int64_t r1, int64_t c0, int64_t c1, In<int64_t> spans, int64_t threads) {
        need(out.ndim() == 3 && out.shape(2) == 3, "out: H x W x 3");
        int64_t h = int64_t(out.shape(0)), w = int64_t(out.shape(1));
        check_planes(y, u, v, h, w, hx, vy);
        need(0 <= r0 && r0 <= r1 && r1 <= h && 0 <= c0 && c0 <= c1 && c1 <= w, "the window is outside the frame");
        need(range.size() == 4 && matrix.size() == 9 && table.size() == 2 * 65536, "range 4, matrix 9, table 2 x 65536");
        need(primaries.size() == 0 || primaries.size() == 9, "primaries: 3 x 3 or empty");
        const double* g = range.data();
        Range r{g[0], g[1], g[2], g[3]};
        const double* pm = primaries.size() ? primaries.data() : nullptr;
        need(rb.size() == 0 || (rb.size() == 2 * 65536 && y.dtype() == nb::dtype<uint8_t>()),
             "rb: empty, or the tables of 8-bit samples (2 x 256 x 256)");
        const float* tables = rb.size() ? rb.data() : nullptr;
        need(spans.size() == 0 || spans.size() == size_t(4 * h), "spans: empty, or each row's two spans of columns");
        const int64_t* sp = spans.size() ? spans.data() : nullptr;
        if (y.dtype() == nb::dtype<uint8_t>())
            to_linear(planes_of<const uint8_t>(y, u, v, hx, vy), r, matrix.data(), table.data(), tables, pm,
                      out.data(), w, r0, r1, c0, c1, sp, threads);
        else
            to_linear(planes_of<const uint16_t>(y, u, v, hx, vy), r, matrix.data(), table.data(), nullptr, pm,
                      out.data(), w, r0, r1, c0, c1, sp, threads);
    }, nb::arg("y"), nb::arg("u"), nb::arg("v"), nb::arg("hx"), nb::arg("vy"), nb::arg("range"), nb::arg("matrix"),
       nb::arg("table"), nb::arg("rb"), nb::arg("primaries"), nb::arg("out").noconvert(), nb::arg("r0"), nb::arg("r1"),
       nb::arg("c0"), nb::arg("c1"), nb::arg("spans"), nb::arg("threads"), nb::call_guard<nb::gil_scoped_release>());

    m.def("linear_to_ycbcr", [](In<float> lin, In<double> primaries, In<float> table, uint32_t b0, int shift,
                                float zero, In<double> matrix, In<double> range, double top, Plane y, Plane u,
                                Plane v, int hx, int vy, int64_t threads) {
        need(lin.ndim() == 3 && lin.shape(2) == 3, "lin: H x W x 3");
        int64_t h = int64_t(lin.shape(0)), w = int64_t(lin.shape(1));
        check_planes(y, u, v, h, w, hx, vy);
        need(primaries.size() == 0 || primaries.size() == 9, "primaries: 3 x 3 or empty");
        need(table.size() == 0 || table.size() >= 2, "a table of two knots at least");
        need(range.size() == 4 && matrix.size() == 9, "range 4, matrix 9");
        need(0 <= shift && shift < 32, "shift: 0 to 31");
        Curve c{table.size() ? table.data() : nullptr, int64_t(table.size()), b0, shift, zero};
        const double* g = range.data();
        Range r{g[0], g[1], g[2], g[3]};
        const double* pm = primaries.size() ? primaries.data() : nullptr;
        if (y.dtype() == nb::dtype<uint8_t>())
            from_linear(lin.data(), h, w, pm, c, matrix.data(), r, top, planes_of<uint8_t>(y, u, v, hx, vy), threads);
        else
            from_linear(lin.data(), h, w, pm, c, matrix.data(), r, top, planes_of<uint16_t>(y, u, v, hx, vy), threads);
    }, nb::arg("lin"), nb::arg("primaries"), nb::arg("table"), nb::arg("b0"), nb::arg("shift"), nb::arg("zero"),
       nb::arg("matrix"), nb::arg("range"), nb::arg("top"), nb::arg("y").noconvert(), nb::arg("u").noconvert(),
       nb::arg("v").noconvert(), nb::arg("hx"), nb::arg("vy"), nb::arg("threads"),
       nb::call_guard<nb::gil_scoped_release>());
}
