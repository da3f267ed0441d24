// Shared windows for the footprint filter (src/native/footprint_runs.cpp): the footprints of a run of consecutive
// samples in one output row read the texels of one window, loaded once with its rows' prefix sums, instead of one
// window each (NumPy reference: lenslab.warp.kernels.reference.footprint, which reads each footprint through its own
// window: the same integral).
//
// The window is ragged: slice row v holds the texels [lo[v], hi[v]) only, the union of the windows of the
// footprints that read that row. Each row's prefix sums start at its own first texel. That moves F (the integral
// along the row, footprint_edges.h) by a constant per row, and between two texel rows F is the linear mix of
// the two: the shift is a function of y alone, whose integral around a closed contour is zero. Each footprint's
// integral is therefore the one its own window gives, but for float64 rounding: F sums at most CAP texels, so its
// rounding error is below about CAP * 2^-53 of the sum of their magnitudes (2.3e-13 of it), against the
// footprint's own integral of the same texels.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "footprint_edges.h"

namespace lenslab {
namespace footprint_edges {

constexpr int CHUNK = 16;  // consecutive samples of an output row that may share a window
constexpr int MAXR = 80;  // slice rows a shared window spans
constexpr int64_t CAP = 2048;  // texels a shared window holds (a seam or a jump in the map starts a new one)

// A footprint's place in its window: its slice rows [v0, v0 + nv) and the texels [u0, u0 + nu) of each.
struct Span {
    int64_t u0, v0, nu, nv;
};

// The rows of one footprint's window, as edge_integral reads them: pointers into a shared ragged window, each at
// the footprint's first texel u0 of that row.
template <int NC>
struct RowPtrs {
    typedef typename Lanes<NC>::type L;
    const L* f[WINDOW];
    const L* h[WINDOW];
    const L* s[WINDOW];
};

// The union of the windows of a group of footprints (all of one level and one slicing direction).
template <int NC>
struct Ragged {
    typedef typename Lanes<NC>::type L;
    int64_t vb = 0;  // slice row of lo[0]
    int64_t vlo = 0, vhi = 0;  // the rows in use: [vlo, vhi)
    int64_t lo[MAXR], hi[MAXR], base[MAXR];
    L vmin{}, vmax{};  // the least and greatest texel the window holds (each channel), after load
    std::vector<L> f, h, s;
    Ragged() : f(CAP), h(CAP), s(CAP) {}

    // the rows [v0, v1) (at most MAXR), empty
    void start(int64_t v0, int64_t v1) {
        vb = vlo = v0;
        vhi = v1;
        for (int64_t r = 0; r < v1 - v0; ++r) { lo[r] = INT64_MAX; hi[r] = INT64_MIN; }
    }
    // the window w joins the union (its rows inside [vlo, vhi))
    void add(const Span& w) {
        for (int64_t v = w.v0; v < w.v0 + w.nv; ++v) {
            const int64_t r = v - vb;
            lo[r] = std::min(lo[r], w.u0);
            hi[r] = std::max(hi[r], w.u0 + w.nu);
        }
    }

    // the texels of every row (channels c0 .. c0 + cn) with their prefix sums (as load_rows, from each row's first);
    // false if a texel is not finite (a prefix sum would carry it along the rest of its row, into footprints that
    // do not read that texel: each footprint is then read through its own window)
    bool load(const float* __restrict__ buf, int64_t lw, int64_t lh, int64_t nc_, int64_t c0, int64_t cn, Border b,
              bool cols) {
        const int64_t nc = NC > 0 ? NC : nc_;
        const float* end = buf + lw * lh * nc;
        int64_t at = 0;
        L ends{};  // the rows' last prefix sums and last texels (0 * ends stays 0 while they are finite)
        bool any = false;
        for (int64_t v = vlo; v < vhi; ++v) {
            const int64_t r = v - vb;
            base[r] = at;
            if (lo[r] >= hi[r]) continue;
            const int64_t n = hi[r] - lo[r];
            L* F = f.data() + at;
            const int64_t x0 = cols ? v : lo[r], y0 = cols ? lo[r] : v;  // texel lo[r] of the row
            const bool inside = cols ? (x0 >= 0 && x0 < lw && y0 >= 0 && y0 + n <= lh)
                                     : (y0 >= 0 && y0 < lh && x0 >= 0 && x0 + n <= lw);
            if (inside) {
                const int64_t step = cols ? lw * nc : nc;
                const float* t = buf + (y0 * lw + x0) * nc;
                for (int64_t u = 0; u < n; ++u, t += step) F[u] = load_texel<NC>(t, t + 4 > end, c0, cn);
            } else {
                for (int64_t u = 0; u < n; ++u) {
                    int64_t ii = cols ? x0 : x0 + u, jj = cols ? y0 + u : y0;
                    fold_index(ii, jj, lw, lh, b.wrap, b.top, b.bottom);
                    const float* t = buf + (jj * lw + ii) * nc;
                    F[u] = load_texel<NC>(t, t + 4 > end, c0, cn);
                }
            }
            L* H = h.data() + at;
            L* S = s.data() + at;
            L acc{};  // (zero: a texel of inf would make 0 * inf NaN)
            L mn = any ? lane_min(vmin, F[n - 1]) : F[n - 1], mx = any ? lane_max(vmax, F[n - 1]) : F[n - 1];
            any = true;
            for (int64_t u = 0; u + 1 < n; ++u) {
                S[u] = acc;
                H[u] = 0.5 * (F[u + 1] - F[u]);
                acc = acc + 0.5 * (F[u] + F[u + 1]);
                mn = lane_min(mn, F[u]);
                mx = lane_max(mx, F[u]);
            }
            vmin = mn;
            vmax = mx;
            ends = ends + 0.0 * (acc + F[n - 1]);
            at += n;
        }
        bool finite;
        if constexpr (NC == 1) finite = ends == 0.0;
        else finite = ends[0] == 0.0 && ends[1] == 0.0 && ends[2] == 0.0 && ends[3] == 0.0;
        if (!finite) {  // (no bound: the means are not clamped)
            vmin = L{} - INFINITY;
            vmax = L{} + INFINITY;
        }
        return finite;
    }

    // the rows of a footprint's window w (inside the union)
    void rows(const Span& w, RowPtrs<NC>& R) const {
        for (int64_t j = 0; j < w.nv; ++j) {
            const int64_t r = w.v0 + j - vb;
            const int64_t o = base[r] + (w.u0 - lo[r]);
            R.f[j] = f.data() + o;
            R.h[j] = h.data() + o;
            R.s[j] = s.data() + o;
        }
    }
};

}  // namespace footprint_edges
}  // namespace lenslab
