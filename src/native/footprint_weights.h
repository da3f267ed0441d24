// The footprint filter's texel weights (src/native/footprint_runs.cpp), for a footprint beyond the coarsest pyramid
// level that its window clips: the bilinear reconstruction's weight of each texel of the window, averaged over the
// parallelogram slice by slice, and the texels summed with those weights (NumPy reference:
// lenslab.warp.kernels.reference.slice_weights). Included by footprint_runs.cpp only.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "footprint_edges.h"
#include "kernels.h"

namespace lenslab {
namespace footprint_edges {

constexpr int LANES = 8;  // texels a slice's weights are computed for at once (one AVX-512 vector of doubles)
constexpr int STRIDE = WINDOW + LANES;  // a row of the weights, with room for the last lanes

// The tent's antiderivative (0 below -1, 1 above 1).
inline double tent_c(double u) {
    double v = std::min(1.0, std::max(-1.0, u));
    return 0.5 + v - 0.5 * v * std::fabs(v);
}

// Texel weights of the bilinear reconstruction averaged over the parallelogram c + s a + r b (s, r in
// [-1/2, 1/2]), added into wgt: texel (wx0 + i, wy0 + j) at wgt[j * stride + i], for j from -1 to nwy (the
// rows -1 and nwy are scratch, so that the inner loop has no branch and vectorises). The parallelogram is sliced along its
// rows: between consecutive breakpoints in y (its vertices and the texel rows, where the reconstruction
// bends) each texel's weight is integrated over y by 2-point Gauss-Legendre; along x each slice is
// integrated exactly (the tent's antiderivative). Returns the sum of the weights, the parallelogram's area
// (exact: the slice's width is linear in y between breakpoints).
inline double slice_weights(double cx, double cy, double ax, double ay, double bx, double by, int64_t wx0, int64_t wy0,
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

}  // namespace footprint_edges
}  // namespace lenslab
