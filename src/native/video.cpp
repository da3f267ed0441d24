// Video colour passes (lenslab.cxx_kernels, registered by register_video): decoded 16-bit R'G'B' codes to linear
// light by the transfer function's table, and linear light back to 16-bit codes by a table of its inverse. Each runs without the GIL on `threads` threads of its own, bands of rows each.
// NumPy references: lenslab/io/video_colour.py (the tests compare them).
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

using lenslab::bind::In;
using lenslab::bind::Out;

// 16-bit codes -> linear float32 by `table` (65536); `m` (9 doubles, row-major) applied after the table when given
// (BT.2020 -> Rec.709), the products summed in float64 in the order r, g, b. `out` is a rows x cols x 3 frame;
// `codes` (crows x ccols x 3) is the part of it from row cr0, column cc0 on (the whole frame, or a crop of it
// around the window). Only the window rows [r0, r1) x columns [c0, c1) of `out` is written (the pixels a warp
// reads); the rest is left as it is.
void linear_from_codes(const uint16_t* codes, int64_t ccols, int64_t cr0, int64_t cc0, int64_t cols, int64_t r0,
                       int64_t r1, int64_t c0, int64_t c1, const float* t32, const double* t64, const double* m,
                       float* out, int64_t threads) {
    bands(r1 - r0, threads, 1, [=](int64_t b0, int64_t b1) {
        for (int64_t j = r0 + b0; j < r0 + b1; ++j) {
            const uint16_t* c = codes + ((j - cr0) * ccols + (c0 - cc0)) * 3;
            float* o = out + (j * cols + c0) * 3;
            int64_t n = c1 - c0;
            if (m == nullptr) {
                for (int64_t q = 0; q < n * 3; ++q) o[q] = t32[c[q]];
                continue;
            }
            for (int64_t q = 0; q < n; ++q) {
                double r = t64[c[3 * q]], g = t64[c[3 * q + 1]], b = t64[c[3 * q + 2]];
                for (int k = 0; k < 3; ++k) o[3 * q + k] = float(m[3 * k] * r + m[3 * k + 1] * g + m[3 * k + 2] * b);
            }
        }
    });
}

// Linear float32 (n x 3) -> 16-bit code values: NaN -> 0, +inf -> 1e4, -inf -> 0 (as numpy.nan_to_num), `m`
// (Rec.709 -> the stream's primaries) when given, then the inverse transfer function (curve.table == nullptr:
// values already encoded), clamped to [0, 1]; rounded half to even, as numpy.round.
void codes_from_linear(const float* lin, int64_t rows, int64_t cols, const double* m, Curve curve, uint16_t* out,
                       int64_t threads) {
    bands(rows, threads, 1, [=](int64_t r0, int64_t r1) {
        for (int64_t q = r0 * cols; q < r1 * cols; ++q) {
            float x[3];
            for (int k = 0; k < 3; ++k) {
                float a = lin[3 * q + k];
                x[k] = lenslab_video::finite(a);
            }
            if (m != nullptr) {
                double a = x[0], b = x[1], d = x[2];
                for (int k = 0; k < 3; ++k) x[k] = float(m[3 * k] * a + m[3 * k + 1] * b + m[3 * k + 2] * d);
            }
            for (int k = 0; k < 3; ++k) {
                float v = curve.table != nullptr ? curve(x[k]) : x[k];  // the table runs on past 1: clamp here
                v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
                out[3 * q + k] = uint16_t(std::nearbyint(double(v) * 65535.0));
            }
        }
    });
}

}  // namespace

void register_video(nb::module_& m) {
    m.def("linear_from_codes", [](In<uint16_t> codes, In<float> t32, In<double> t64, In<double> matrix,
                                  Out<float> out, int64_t r0, int64_t r1, int64_t c0, int64_t c1, int64_t cr0,
                                  int64_t cc0, int64_t threads) {
        need(codes.ndim() == 3 && codes.shape(2) == 3 && out.ndim() == 3 && out.shape(2) == 3, "H x W x 3 arrays");
        int64_t h = int64_t(out.shape(0)), w = int64_t(out.shape(1));
        int64_t ch = int64_t(codes.shape(0)), cw = int64_t(codes.shape(1));
        need(0 <= r0 && r0 <= r1 && r1 <= h && 0 <= c0 && c0 <= c1 && c1 <= w, "the window is outside the frame");
        need(r0 == r1 || c0 == c1 || (cr0 <= r0 && r1 <= cr0 + ch && cc0 <= c0 && c1 <= cc0 + cw),
             "the codes do not cover the window");
        bool wide = matrix.size() == 9;
        need(wide ? t64.size() == 65536 : t32.size() == 65536, "a table of 65536 values");
        linear_from_codes(codes.data(), cw, cr0, cc0, w, r0, r1, c0, c1, t32.data(), t64.data(),
                          wide ? matrix.data() : nullptr, out.data(), threads);
    }, nb::arg("codes"), nb::arg("t32"), nb::arg("t64"), nb::arg("matrix"), nb::arg("out").noconvert(),
       nb::arg("r0"), nb::arg("r1"), nb::arg("c0"), nb::arg("c1"), nb::arg("cr0"), nb::arg("cc0"),
       nb::arg("threads"), nb::call_guard<nb::gil_scoped_release>());

    m.def("codes_from_linear", [](In<float> lin, In<double> matrix, In<float> table, uint32_t b0, int shift,
                                  float zero, Out<uint16_t> out, int64_t threads) {
        need(lin.ndim() == 3 && lin.shape(2) == 3, "lin: H x W x 3");
        need(out.size() == lin.size(), "out: the image's shape");
        need(matrix.size() == 0 || matrix.size() == 9, "matrix: 3 x 3 or empty");
        need(table.size() == 0 || table.size() >= 2, "a table of two knots at least");
        need(0 <= shift && shift < 32, "shift: 0 to 31");
        Curve c{table.size() ? table.data() : nullptr, int64_t(table.size()), b0, shift, zero};
        codes_from_linear(lin.data(), int64_t(lin.shape(0)), int64_t(lin.shape(1)),
                          matrix.size() ? matrix.data() : nullptr, c, out.data(), threads);
    }, nb::arg("lin"), nb::arg("matrix"), nb::arg("table"), nb::arg("b0"), nb::arg("shift"), nb::arg("zero"),
       nb::arg("out").noconvert(), nb::arg("threads"), nb::call_guard<nb::gil_scoped_release>());
}
