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

// Y'CbCr planes -> linear float32 in the window [r0, r1) x [c0, c1) of `out` (rows x cols x 3), in float32. With
// `k` the Y'CbCr -> R'G'B' matrix (its first column is 1): 65535 E'q = LY[Y] + (k[q][1] LC[Cb] + k[q][2] LC[Cr]),
// LY and LC the codes' values times 65535 (tables rounded once from float64, so white is 65535 exactly), the
// bracket once per chroma sample; then the transfer function's table, then `m` (BT.2020 -> Rec.709) when given.
template <typename T>
void to_linear(Planes<const T> p, Range r, const double* k, const float* t, const double* m, float* out,
               int64_t cols, int64_t r0, int64_t r1, int64_t c0, int64_t c1, int64_t threads) {
    constexpr int64_t N = int64_t(1) << (8 * sizeof(T));
    std::vector<float> ly(N), lc(N);
    for (int64_t c = 0; c < N; ++c) {
        ly[size_t(c)] = float((double(c) - r.y0) / r.ys * 65535.0);
        lc[size_t(c)] = float((double(c) - r.c0) / r.cs * 65535.0);
    }
    const float kb[3] = {float(k[1]), float(k[4]), float(k[7])}, kr[3] = {float(k[2]), float(k[5]), float(k[8])};
    float mf[9];
    for (int q = 0; q < 9; ++q) mf[q] = m ? float(m[q]) : 0.0f;
    const float* LY = ly.data();
    const float* LC = lc.data();
    bands(r1 - r0, threads, 1, [=](int64_t b0, int64_t b1) {
        int64_t k0 = c0 >> p.hx, k1 = ((c1 - 1) >> p.hx) + 1, n = (c1 - c0) * 3;
        std::vector<float> chroma(size_t(std::max<int64_t>(k1 - k0, 0)) * 3), xs(size_t(std::max<int64_t>(n, 0)));
        for (int64_t j = r0 + b0; j < r0 + b1; ++j) {
            const T* yr = p.y + j * p.sy_;
            const T* ur = p.u + (j >> p.vy) * p.su;
            const T* vr = p.v + (j >> p.vy) * p.sv;
            float* ch = chroma.data() - 3 * k0;
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
            if (m != nullptr) {
                for (int64_t c = 0; c < c1 - c0; ++c) {
                    float e0 = o[3 * c], e1 = o[3 * c + 1], e2 = o[3 * c + 2];
                    for (int q = 0; q < 3; ++q) o[3 * c + q] = mf[3 * q] * e0 + mf[3 * q + 1] * e1 + mf[3 * q + 2] * e2;
                }
            }
        }
    });
}

template <typename T>
void from_linear(const float* lin, int64_t rows, int64_t cols, const double* m, Curve curve, const double* k, Range r,
                 double top, Planes<T> p, int64_t threads) {
    int64_t bw = int64_t(1) << p.hx, bh = int64_t(1) << p.vy, ccols = (cols + bw - 1) / bw;
    auto code = [top](double x) { return T(std::nearbyint(x > 0.0 ? (x < top ? x : top) : 0.0)); };
    bands(rows, threads, bh, [=](int64_t j0, int64_t j1) {
        std::vector<double> acc(size_t(ccols) * 3);
        std::vector<float> es(size_t(cols) * 3);
        float* e = es.data();
        const int64_t n = cols * 3;
        for (int64_t jb = j0; jb < j1; jb += bh) {
            std::fill(acc.begin(), acc.end(), 0.0);
            int64_t je = std::min(j1, jb + bh);
            for (int64_t j = jb; j < je; ++j) {
                const float* a = lin + j * cols * 3;
                for (int64_t q = 0; q < n; ++q) e[q] = lenslab_video::finite(a[q]);
                if (m != nullptr) {
                    for (int64_t c = 0; c < cols; ++c) {
                        float y0 = e[3 * c], y1 = e[3 * c + 1], y2 = e[3 * c + 2];
                        for (int q = 0; q < 3; ++q)
                            e[3 * c + q] = float(m[3 * q] * y0 + m[3 * q + 1] * y1 + m[3 * q + 2] * y2);
                    }
                }
                // one plain loop over the row's values, which the compiler turns into vector gathers
                if (curve.table != nullptr) {
                    for (int64_t q = 0; q < n; ++q) e[q] = lenslab_video::curve_flat(curve, e[q]);
                }
                for (int64_t q = 0; q < n; ++q) e[q] = e[q] > 0.0f ? (e[q] < 1.0f ? e[q] : 1.0f) : 0.0f;
                for (int64_t c = 0; c < cols; ++c) {
                    double w[3];
                    for (int q = 0; q < 3; ++q)
                        w[q] = k[3 * q] * e[3 * c] + k[3 * q + 1] * e[3 * c + 1] + k[3 * q + 2] * e[3 * c + 2];
                    p.y[j * p.sy_ + c] = code(w[0] * r.ys + r.y0);
                    acc[size_t(c >> p.hx) * 2] += w[1];
                    acc[size_t(c >> p.hx) * 2 + 1] += w[2];
                }
            }
            int64_t n_rows = je - jb;
            for (int64_t cc = 0; cc < ccols; ++cc) {
                double nb = double(n_rows * (std::min(cols, (cc + 1) * bw) - cc * bw));
                p.u[(jb >> p.vy) * p.su + cc] = code(acc[size_t(cc) * 2] / nb * r.cs + r.c0);
                p.v[(jb >> p.vy) * p.sv + cc] = code(acc[size_t(cc) * 2 + 1] / nb * r.cs + r.c0);
            }
        }
    });
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
    m.def("ycbcr_to_linear", [](Plane y, Plane u, Plane v, int hx, int vy, In<double> range, In<double> matrix,
                                In<float> table, In<double> primaries, Out<float> out, int64_t r0, int64_t r1,
                                int64_t c0, int64_t c1, int64_t threads) {
        need(out.ndim() == 3 && out.shape(2) == 3, "out: H x W x 3");
        int64_t h = int64_t(out.shape(0)), w = int64_t(out.shape(1));
        check_planes(y, u, v, h, w, hx, vy);
        need(0 <= r0 && r0 <= r1 && r1 <= h && 0 <= c0 && c0 <= c1 && c1 <= w, "the window is outside the frame");
        need(range.size() == 4 && matrix.size() == 9 && table.size() == 2 * 65536, "range 4, matrix 9, table 2 x 65536");
        need(primaries.size() == 0 || primaries.size() == 9, "primaries: 3 x 3 or empty");
        const double* g = range.data();
        Range r{g[0], g[1], g[2], g[3]};
        const double* pm = primaries.size() ? primaries.data() : nullptr;
        if (y.dtype() == nb::dtype<uint8_t>())
            to_linear(planes_of<const uint8_t>(y, u, v, hx, vy), r, matrix.data(), table.data(), pm, out.data(), w,
                      r0, r1, c0, c1, threads);
        else
            to_linear(planes_of<const uint16_t>(y, u, v, hx, vy), r, matrix.data(), table.data(), pm, out.data(), w,
                      r0, r1, c0, c1, threads);
    }, nb::arg("y"), nb::arg("u"), nb::arg("v"), nb::arg("hx"), nb::arg("vy"), nb::arg("range"), nb::arg("matrix"),
       nb::arg("table"), nb::arg("primaries"), nb::arg("out").noconvert(), nb::arg("r0"), nb::arg("r1"),
       nb::arg("c0"), nb::arg("c1"), nb::arg("threads"), nb::call_guard<nb::gil_scoped_release>());

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
