// The footprint prefilter: each output sample averages the bilinear source over its footprint, a
// parallelogram read from the finest pyramid level at which it spans at most max_taps texels (see
// lenslab/warp/antialias.py for the method). By Green's theorem, edge by edge: the integral over y of F at the
// right ends of the parallelogram's rows less F at the left ends, F the integral of the row's linear interpolant
// from the window's first texel (per-row prefix sums of the window: O(1) per point, whatever the width), each
// edge cut at the texel rows and integrated by 2-point Gauss-Legendre. In float64, in the order of the NumPy
// reference (lenslab.warp.kernels.reference.prefix_slices); a footprint clipped by its window (beyond the
// coarsest level) takes the texel weights of the slices instead (reference.slice_weights). The edge integrals
// are in footprint_edges.h.
#include <algorithm>
#include <climits>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include "bind.h"
#include "footprint_edges.h"
#include "sampler.h"

namespace lenslab {
namespace {

using namespace footprint_edges;

constexpr int LANES = 8;  // texels a slice's weights are computed for at once (one AVX-512 vector of doubles)
constexpr int STRIDE = WINDOW + LANES;  // a row of the weights, with room for the last lanes
constexpr double THIN = 1e-3;  // texels: a box narrower than this is read as a line (error ~THIN^2)

// The tent's antiderivative (0 below -1, 1 above 1).
inline double tent_c(double u) {
    double v = std::min(1.0, std::max(-1.0, u));
    return 0.5 + v - 0.5 * v * std::fabs(v);
}

inline int64_t ifloor(double v) { return int64_t(bfloor(v)); }

// a footprint side as the filter reads it: NaN a point (0), beyond +-2^40 texels (inf included) +-2^40
inline double clamp_side(float v) { return v == v ? double(clamp_pos(v)) : 0.0; }

// Texel weights of the bilinear reconstruction averaged over the parallelogram c + s a + r b (s, r in
// [-1/2, 1/2]), added into wgt: texel (wx0 + i, wy0 + j) at wgt[j * stride + i], for j from -1 to nwy (the
// rows -1 and nwy are scratch, so that the inner loop has no branch and vectorises). The parallelogram is sliced along its
// rows: between consecutive breakpoints in y (its vertices and the texel rows, where the reconstruction
// bends) each texel's weight is integrated over y by 2-point Gauss-Legendre; along x each slice is
// integrated exactly (the tent's antiderivative). Returns the sum of the weights, the parallelogram's area
// (exact: the slice's width is linear in y between breakpoints).
double slice_weights(double cx, double cy, double ax, double ay, double bx, double by, int64_t wx0, int64_t wy0,
                     int64_t nwx, int64_t nwy, double* wgt, int64_t stride) {
    const double vx[4] = {cx - 0.5 * ax - 0.5 * bx, cx + 0.5 * ax - 0.5 * bx, cx + 0.5 * ax + 0.5 * bx,
                          cx - 0.5 * ax + 0.5 * bx};
    const double vy[4] = {cy - 0.5 * ay - 0.5 * by, cy + 0.5 * ay - 0.5 * by, cy + 0.5 * ay + 0.5 * by,
                          cy - 0.5 * ay + 0.5 * by};
    double lo[4], hi[4], x0[4], k[4];  // each edge: its y range, x at its low end, dx/dy
    for (int e = 0; e < 4; ++e) {
        const int f = (e + 1) & 3;
        const bool up = vy[e] <= vy[f];
        lo[e] = up ? vy[e] : vy[f];
        hi[e] = up ? vy[f] : vy[e];
        x0[e] = up ? vx[e] : vx[f];
        k[e] = hi[e] > lo[e] ? ((up ? vx[f] : vx[e]) - x0[e]) / (hi[e] - lo[e]) : 0.0;
    }
    // the vertices' y in order (a sorting network: no branch to mispredict)
    const double a0 = std::min(vy[0], vy[1]), a1 = std::max(vy[0], vy[1]);
    const double a2 = std::min(vy[2], vy[3]), a3 = std::max(vy[2], vy[3]);
    const double m1 = std::max(a0, a2), m2 = std::min(a1, a3);
    const double ys[4] = {std::min(a0, a2), std::min(m1, m2), std::max(m1, m2), std::max(a1, a3)};
    const double g2 = 0.5 / std::sqrt(3.0);
    // only the slices of the window's rows (-1 to nwy - 1) are integrated: a footprint inside its window
    // starts and ends within them (the same slices, the same bits); one clipped by the window takes its sum
    // from the weights, not from the area, and costs its window, not its length (2^40 rows at the most)
    const double y_end = std::min(ys[3], double(wy0 + nwy));
    double total = 0.0, y = std::max(ys[0], double(wy0 - 1));
    int v = 1, seen = 0, le = 0, re = 0;
    while (y < y_end) {
        while (v < 3 && ys[v] <= y) ++v;
        if (v != seen) {  // a new pair of vertices: the edges on the left and on the right until the next
            seen = v;
            const double ym = 0.5 * (ys[v - 1] + ys[v]);
            double bl = 1e300, br = -1e300;
            le = re = 0;
            for (int e = 0; e < 4; ++e) {
                if (ym < lo[e] || ym > hi[e] || hi[e] == lo[e]) continue;
                const double x = x0[e] + (ym - lo[e]) * k[e];
                if (x < bl) { bl = x; le = e; }
                if (x > br) { br = x; re = e; }
            }
        }
        const double y1 = std::min(ys[v], bfloor(y) + 1.0);
        const double len = y1 - y, mid = 0.5 * (y + y1), g = 0.5 * len;
        // both Gauss points lie between the same two texel rows: one pass over the texels for the two
        double xl[2], xr[2], w0[2], w1[2];
        const double fm = bfloor(mid);
        const int64_t j = int64_t(fm) - wy0;
        for (int p = 0; p < 2; ++p) {
            const double yy = p == 0 ? mid - g2 * len : mid + g2 * len;
            xl[p] = x0[le] + (yy - lo[le]) * k[le];
            xr[p] = std::max(xl[p], x0[re] + (yy - lo[re]) * k[re]);
            total += g * (xr[p] - xl[p]);
            const double ty = yy - fm;
            w0[p] = g * (1.0 - ty);
            w1[p] = g * ty;
        }
        if (j >= -1 && j < nwy) {  // (always, for a footprint inside its window)
            const double lo_x = std::min(xl[0], xl[1]), hi_x = std::max(xr[0], xr[1]);
            const int64_t i0 = std::max<int64_t>(ifloor(lo_x - 1.0) + 1 - wx0, 0);
            const int64_t i1 = std::min<int64_t>(ifloor(hi_x + 1.0) + 1 - wx0, nwx);
            double* __restrict__ row0 = wgt + j * stride;
            double* __restrict__ row1 = row0 + stride;
            const double dl0 = xl[0] - double(wx0), dr0 = xr[0] - double(wx0);
            const double dl1 = xl[1] - double(wx0), dr1 = xr[1] - double(wx0);
            // LANES texels at a time (the rows have room): beyond i1 both ends' antiderivatives are 0, so
            // the extra texels get exactly 0 and the weights are those of the loop up to i1
            for (int64_t b = i0; b < i1; b += LANES) {
                for (int64_t l = 0; l < LANES; ++l) {
                    const double t = double(b + l);
                    const double wa = tent_c(dr0 - t) - tent_c(dl0 - t);
                    const double wb = tent_c(dr1 - t) - tent_c(dl1 - t);
                    row0[b + l] += w0[0] * wa + w0[1] * wb;
                    row1[b + l] += w1[0] * wa + w1[1] * wb;
                }
            }
        }
        y = y1;
    }
    return total;
}

// acc += the texels of the window (wx0, wy0, nwx, nwy) times their weights: texel (wx0 + i, wy0 + j) at
// wgt[j * stride + i], or at wgt[i * stride + j] when T (the weights were sliced along columns)
template <int NC, bool T>
inline void gather(const float* __restrict__ buf, int64_t lw, int64_t lh, int64_t nc_, Border b, int64_t wx0,
                   int64_t wy0, int64_t nwx, int64_t nwy, const double* wgt, int64_t stride, double* acc) {
    const int64_t nc = NC > 0 ? NC : nc_;
    const bool inside = wx0 >= 0 && wy0 >= 0 && wx0 + nwx <= lw && wy0 + nwy <= lh;
    const int64_t si = T ? stride : 1, sj = T ? 1 : stride;
    for (int64_t j = 0; j < nwy; ++j) {
        const double* wr = wgt + j * sj;
        if (inside) {
            const float* t = buf + ((wy0 + j) * lw + wx0) * nc;
            for (int64_t i = 0; i < nwx; ++i)
                for (int64_t ch = 0; ch < nc; ++ch) acc[ch] += wr[i * si] * double(t[i * nc + ch]);
            continue;
        }
        for (int64_t i = 0; i < nwx; ++i) {
            int64_t ii = wx0 + i, jj = wy0 + j;
            fold_index(ii, jj, lw, lh, b.wrap, b.top, b.bottom);
            const float* t = buf + (jj * lw + ii) * nc;
            for (int64_t ch = 0; ch < nc; ++ch) acc[ch] += wr[i * si] * double(t[ch]);
        }
    }
}

// NC > 0: that many channels, known to the compiler; NC == 0: nc (<= 64) at run time
template <int NC>
void footprint_t(const float* __restrict__ level0, const float* __restrict__ rest, const int64_t* shapes,
                 const int64_t* offsets, int64_t nlev, int64_t nc_, const float* __restrict__ xs,
                 const float* __restrict__ ys, const bool* __restrict__ valid, const float* __restrict__ foot,
                 int64_t npix, int64_t ns, Border b, double max_taps, float* __restrict__ out,
                 float* __restrict__ alpha) {
    const int64_t nc = NC > 0 ? NC : nc_;
    const double inv = 1.0 / double(ns);
    const double h0 = double(shapes[0]);
    double wgt[(WINDOW + 2) * STRIDE];
    std::vector<Rows<NC>> rows_buf(1);  // (110 kB: on the heap)
    Rows<NC>* rows = rows_buf.data();
    double acc[NC > 0 ? NC : 64];
    for (int64_t q = 0; q < npix; ++q) {
        for (int64_t ch = 0; ch < nc; ++ch) acc[ch] = 0.0;
        int64_t hits = 0;
        for (int64_t s = q * ns; s < (q + 1) * ns; ++s) {
            if (!valid[s]) continue;
            ++hits;
            const float* f = foot + 4 * s;
            const double fax = clamp_side(f[0]), fay = clamp_side(f[1]), fbx = clamp_side(f[2]), fby = clamp_side(f[3]);
            const double la = fax * fax + fay * fay, lb = fbx * fbx + fby * fby;
            int64_t lev = 0;
            if (std::max(la, lb) > max_taps * max_taps) {  // beyond level 0 (the square roots only then)
                const double longest = std::max(std::sqrt(la), std::sqrt(lb));
                while (lev + 1 < nlev && longest > max_taps * double(int64_t(1) << lev)) ++lev;
            }
            const int64_t lh = shapes[2 * lev], lw = shapes[2 * lev + 1];
            const double scale = double(lh) / h0;
            const double ax = fax * scale, ay = fay * scale, bx = fbx * scale, by = fby * scale;
            const double cx = (double(clamp_pos(xs[s])) + 0.5) * scale - 0.5;  // NaN: the left or top edge
            const double cy = (double(clamp_pos(ys[s])) + 0.5) * scale - 0.5;
            // a degenerate footprint (a line or a point) gets a thickness far below a texel
            double tax = ax, tay = ay, tbx = bx, tby = by;
            if (std::fabs(ax * by - ay * bx) < THIN * THIN) {
                const double la = std::hypot(ax, ay), lb = std::hypot(bx, by);
                if (la >= lb && la > 0.0) { tbx = -THIN * ay / la; tby = THIN * ax / la; }
                else if (lb > 0.0) { tax = THIN * by / lb; tay = -THIN * bx / lb; }
                else { tax = THIN; tay = 0.0; tbx = 0.0; tby = THIN; }
            }
            // the window: every texel the reconstruction over the (thickened) parallelogram touches
            const double ex = 0.5 * (std::fabs(tax) + std::fabs(tbx)) + 1.0, ey = 0.5 * (std::fabs(tay) + std::fabs(tby)) + 1.0;
            int64_t wx0 = ifloor(cx - ex) + 1, wy0 = ifloor(cy - ey) + 1;
            int64_t nwx = ifloor(cx + ex) + 1 - wx0, nwy = ifloor(cy + ey) + 1 - wy0;
            // a footprint beyond the coarsest level: the window is centred on it (its top-left corner may miss a
            // rotated footprint entirely: no weight at all, and 0 / 0)
            if (nwx > WINDOW) { wx0 = ifloor(cx) + 1 - WINDOW / 2; nwx = WINDOW; }
            if (nwy > WINDOW) { wy0 = ifloor(cy) + 1 - WINDOW / 2; nwy = WINDOW; }
            const float* buf = lev == 0 ? level0 : rest;
            const float* lbuf = buf + offsets[lev];
            const bool cols = ey > ex;  // slice along the shorter extent (fewer slices): along columns if x is
            const int64_t nu = cols ? nwy : nwx, nv = cols ? nwx : nwy;  // texels along a slice, slices' rows
            if (nwx < WINDOW && nwy < WINDOW) {  // the footprint inside its window: its rows' prefix sums
                constexpr int64_t GROUP = NC > 0 ? NC : 4;  // channels integrated at once
                for (int64_t c0 = 0; c0 < nc; c0 += GROUP) {
                    const int64_t cn = std::min(GROUP, nc - c0);
                    load_rows<NC>(lbuf, lw, lh, nc, c0, cn, b, cols ? wy0 : wx0, cols ? wx0 : wy0, nu, nv, cols, *rows);
                    typename Lanes<NC>::type part{};
                    const double area = cols ? prefix_slices<NC>(cy - double(wy0), cx - double(wx0), tay, tax, tby, tbx,
                                                                 nu, nv, *rows, part)
                                             : prefix_slices<NC>(cx - double(wx0), cy - double(wy0), tax, tay, tbx, tby,
                                                                 nu, nv, *rows, part);
                    const double norm = 1.0 / area;
                    if constexpr (NC == 1) acc[0] += part * norm;
                    else for (int64_t ch = 0; ch < cn; ++ch) acc[c0 + ch] += part[ch] * norm;
                }
                continue;
            }
            // a footprint beyond the coarsest level, clipped by its window: the texels' weights, summed
            double* const w = wgt + STRIDE;  // row -1 of the weights is scratch
            for (int64_t j = 0; j < nv + 2; ++j) std::fill(wgt + j * STRIDE, wgt + j * STRIDE + nu + LANES, 0.0);
            const double area = cols ? slice_weights(cy, cx, tay, tax, tby, tbx, wy0, wx0, nu, nv, w, STRIDE)
                                     : slice_weights(cx, cy, tax, tay, tbx, tby, wx0, wy0, nu, nv, w, STRIDE);
            double part[NC > 0 ? NC : 64];
            for (int64_t ch = 0; ch < nc; ++ch) part[ch] = 0.0;
            if (cols) gather<NC, true>(lbuf, lw, lh, nc, b, wx0, wy0, nwx, nwy, w, STRIDE, part);
            else gather<NC, false>(lbuf, lw, lh, nc, b, wx0, wy0, nwx, nwy, w, STRIDE, part);
            double sum = area;
            if (nwx == WINDOW || nwy == WINDOW) {  // a footprint beyond the coarsest level: some weights clipped
                sum = 0.0;
                for (int64_t j = 0; j < nv; ++j)
                    for (int64_t i = 0; i < nu; ++i) sum += w[j * STRIDE + i];
            }
            const double norm = 1.0 / sum;
            for (int64_t ch = 0; ch < nc; ++ch) acc[ch] += part[ch] * norm;
        }
        for (int64_t ch = 0; ch < nc; ++ch) out[q * nc + ch] = float(acc[ch] * inv);
        alpha[q] = float(double(hits) * inv);
    }
}

}  // namespace

void footprint(const float* level0, const float* rest, const int64_t* shapes, const int64_t* offsets, int64_t nlev,
               int64_t nc, const float* xs, const float* ys, const bool* valid, const float* foot, int64_t npix,
               int64_t ns, Border b, double max_taps, float* out, float* alpha) {
    switch (nc) {
        case 1: return footprint_t<1>(level0, rest, shapes, offsets, nlev, nc, xs, ys, valid, foot, npix, ns, b, max_taps, out, alpha);
        case 3: return footprint_t<3>(level0, rest, shapes, offsets, nlev, nc, xs, ys, valid, foot, npix, ns, b, max_taps, out, alpha);
        case 4: return footprint_t<4>(level0, rest, shapes, offsets, nlev, nc, xs, ys, valid, foot, npix, ns, b, max_taps, out, alpha);
        default: return footprint_t<0>(level0, rest, shapes, offsets, nlev, nc, xs, ys, valid, foot, npix, ns, b, max_taps, out, alpha);
    }
}

}  // namespace lenslab

// The binding (lenslab.cxx_kernels.footprint), registered by src/native/module.cpp; the GIL is released.
namespace nb = nanobind;

void register_footprint(nb::module_& m) {
    using namespace lenslab;
    using bind::need;
    using InF = bind::In<float>;
    using InI = bind::In<int64_t>;
    using InB = bind::In<bool>;
    using OutF = bind::Out<float>;
    m.def("footprint", [](InF level0, InF rest, InI shapes, InI offsets, InF xs, InF ys, InB valid, InF foot,
                              bool wrap, bool top, bool bottom, double max_taps, OutF out, OutF alpha) {
        size_t npix = alpha.size();
        need(npix > 0 && xs.size() % npix == 0, "band shapes differ");
        size_t ns = xs.size() / npix;
        need(ys.size() == xs.size() && valid.size() == xs.size() && foot.size() == 4 * xs.size(), "band shapes differ");
        need(shapes.ndim() == 2 && shapes.shape(1) == 2 && shapes.shape(0) > 0 && offsets.size() == shapes.shape(0),
             "pyramid shapes");
        int64_t nc = int64_t(out.size() / npix);
        need(out.size() == npix * nc && nc > 0 && nc <= 64, "out must hold whole pixels (at most 64 channels)");
        const int64_t* sp = shapes.data();
        const int64_t* op = offsets.data();
        bool fits = op[0] == 0;  // every level lies inside its buffer
        for (size_t l = 0; l < shapes.shape(0); ++l) {
            const int64_t h = sp[2 * l], w = sp[2 * l + 1];
            fits &= h > 0 && w > 0 && h <= (int64_t(1) << 24) && w <= (int64_t(1) << 24) && op[l] >= 0;
            if (!fits) break;
            const uint64_t end = uint64_t(op[l]) + uint64_t(h * w) * uint64_t(nc);
            fits &= end <= (l == 0 ? level0.size() : rest.size());
        }
        need(fits, "the pyramid's levels must lie inside level0 and rest");
        need(max_taps > 0.0 && max_taps <= 8.0, "max_taps must be in (0, 8] (the window holds 2 max_taps + 3)");
        {
            nb::gil_scoped_release release;
            footprint(level0.data(), rest.data(), shapes.data(), offsets.data(), int64_t(shapes.shape(0)), nc,
                      xs.data(), ys.data(), valid.data(), foot.data(), int64_t(npix), int64_t(ns), {wrap, top, bottom},
                      max_taps, out.data(), alpha.data());
        }
    }, nb::arg("level0"), nb::arg("rest"), nb::arg("shapes"), nb::arg("offsets"), nb::arg("xs"), nb::arg("ys"),
       nb::arg("valid"), nb::arg("foot"), nb::arg("wrap"), nb::arg("top"), nb::arg("bottom"), nb::arg("max_taps"),
       nb::arg("out").noconvert(), nb::arg("alpha").noconvert());
}
