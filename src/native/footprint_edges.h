// The footprint filter's integral over a parallelogram inside its window (src/native/footprint_runs.cpp): the
// window's rows with their prefix sums, and Green's theorem edge by edge (NumPy reference:
// lenslab.warp.kernels.reference.window_rows, edge_integral, prefix_slices). Included by the filter's files and by
// pyramid.cpp, which finds the rows of the levels the filter reads.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>
#if defined(__SSE4_1__) || defined(__AVX__)
#include <immintrin.h>
#endif

#include "kernels.h"

namespace lenslab {
namespace footprint_edges {

constexpr int WINDOW = 24;  // texels: the window a footprint is read through (fits 2 max_taps + 4; pyramid.py)

// floor without a branch to mispredict (one instruction on CPUs with SSE4.1; the positions here are bounded by
// 2^40, where dfloor gives the same value but for -0.0)
inline double bfloor(double v) {
#if defined(__SSE4_1__)
    return _mm_cvtsd_f64(_mm_round_sd(_mm_setzero_pd(), _mm_set_sd(v), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC));
#else
    return dfloor(v);
#endif
}

inline int64_t ifloor(double v) { return int64_t(bfloor(v)); }

// a footprint side as the filter reads it (and pyramid.cpp, for the rows it will read): NaN a point (0), beyond
// +-2^40 texels (inf included) +-2^40
inline double clamp_side(float v) { return v == v ? double(clamp_pos(v)) : 0.0; }

// A texel's channels in float64, as one vector (3 and 4 channels: four lanes, the last one idle for 3; any other
// count (NC = 0) is read in groups of at most four)
typedef double V4 __attribute__((vector_size(32)));
template <int NC> struct Lanes { typedef V4 type; };
template <> struct Lanes<1> { typedef double type; };

// the channels c0 .. c0 + cn (cn <= 4) of texel t; `last`: t + 4 floats may lie beyond the buffer
template <int NC>
inline typename Lanes<NC>::type load_texel(const float* t, bool last, int64_t c0, int64_t cn) {
    if constexpr (NC == 1) {
        return double(t[0]);
    } else if constexpr (NC == 0) {
        V4 v = {0.0, 0.0, 0.0, 0.0};
        for (int64_t c = 0; c < cn; ++c) v[c] = double(t[c0 + c]);
        return v;
    } else {
#if defined(__AVX__)
        if (NC == 4 || !last) {  // (3 channels: one float past the texel is read, then dropped)
            V4 v = _mm256_cvtps_pd(_mm_loadu_ps(t));
            if constexpr (NC == 3) v[3] = 0.0;
            return v;
        }
#endif
        return V4{double(t[0]), double(t[1]), double(t[2]), NC == 4 ? double(t[3]) : 0.0};
    }
}

// each lane's least and greatest of a and b (where b is not a number: a)
inline double lane_min(double a, double b) { return b < a ? b : a; }
inline double lane_max(double a, double b) { return b > a ? b : a; }
inline V4 lane_min(V4 a, V4 b) { return b < a ? b : a; }
inline V4 lane_max(V4 a, V4 b) { return b > a ? b : a; }

// The mean of a footprint, part / area, kept within [lo, hi], the least and greatest texel its window read: the
// exact box average of a bilinear reconstruction is a convex combination of those texels, so this removes only
// float64 rounding (of a prefix sum's constant that cancels around the contour: a value of -7e-14 where a
// non-negative source is 0 beside a bright texel). NaN stays NaN.
template <class L>
inline L clamp_mean(L v, L lo, L hi) {
    v = v < lo ? lo : v;
    return v > hi ? hi : v;
}

// The rows of a window as the slices read them: row r (slices' rows: y; x when the footprint is sliced along
// columns), texel u along it: its value f, half the step to the next texel h = (f[u + 1] - f[u]) / 2, and the
// integral s of the row's linear interpolant from texel 0 to texel u (trapezoids, summed in order), so that
// the integral from texel 0 to u + t (0 <= t <= 1) is s + t (f + t h).
template <int NC>
struct Rows {
    typedef typename Lanes<NC>::type L;
    L f[WINDOW][WINDOW], h[WINDOW][WINDOW], s[WINDOW][WINDOW];
};

// (the channels c0 .. c0 + cn of the nc a texel holds)
template <int NC>
void load_rows(const float* __restrict__ buf, int64_t lw, int64_t lh, int64_t nc_, int64_t c0, int64_t cn, Border b,
               int64_t wu0, int64_t wv0, int64_t nu, int64_t nv, bool cols, Rows<NC>& R) {
    typedef typename Lanes<NC>::type L;
    const int64_t nc = NC > 0 ? NC : nc_;
    const int64_t wx0 = cols ? wv0 : wu0, wy0 = cols ? wu0 : wv0, nwx = cols ? nv : nu, nwy = cols ? nu : nv;
    const bool inside = wx0 >= 0 && wy0 >= 0 && wx0 + nwx <= lw && wy0 + nwy <= lh;
    const float* end = buf + lw * lh * nc;
    for (int64_t r = 0; r < nv; ++r) {
        if (inside) {  // the texels of the row one stride apart
            const int64_t step = cols ? lw * nc : nc;
            const float* t = buf + ((cols ? wu0 : wv0 + r) * lw + (cols ? wv0 + r : wu0)) * nc;
            for (int64_t u = 0; u < nu; ++u, t += step) R.f[r][u] = load_texel<NC>(t, t + 4 > end, c0, cn);
        } else {
            for (int64_t u = 0; u < nu; ++u) {
                int64_t ii = cols ? wv0 + r : wu0 + u, jj = cols ? wu0 + u : wv0 + r;
                fold_index(ii, jj, lw, lh, b.wrap, b.top, b.bottom);
                const float* t = buf + (jj * lw + ii) * nc;
                R.f[r][u] = load_texel<NC>(t, t + 4 > end, c0, cn);
            }
        }
        L acc{};  // (zero: a texel of inf would make 0 * inf NaN)
        for (int64_t u = 0; u + 1 < nu; ++u) {
            R.s[r][u] = acc;
            R.h[r][u] = 0.5 * (R.f[r][u + 1] - R.f[r][u]);
            acc = acc + 0.5 * (R.f[r][u] + R.f[r][u + 1]);
        }
    }
}

// sign * the integral over y of F(x(y), y) along the edge from (xa, ya) to (xb, yb) (ya <= yb), added into acc:
// F(x, y) the integral of the bilinear reconstruction along the slices' row y from the window's first texel to x.
// Cut at the texel rows (where the reconstruction bends in y), each piece by 2-point Gauss-Legendre: exact while
// the edge stays between two texel columns (F is then a cubic along it).
template <int NC, class RowsT>
inline void edge_integral(double xa, double ya, double xb, double yb, double sign, double umax, int64_t jmax,
                          const RowsT& R, typename Lanes<NC>::type& acc) {
    if (!(yb > ya)) return;  // a horizontal edge adds nothing
    const double k = (xb - xa) / (yb - ya);
    const double g2 = 0.5 / std::sqrt(3.0);
    for (double n = bfloor(ya); n < yb; n += 1.0) {
        const double y0 = std::max(ya, n), y1 = std::min(yb, n + 1.0);
        const double len = y1 - y0, mid = 0.5 * (y0 + y1), g = sign * 0.5 * len;
        // the texel rows j and j + 1 around the piece (kept in the window against rounding at its edge)
        const int64_t j = std::min(jmax, std::max<int64_t>(0, int64_t(n)));
        const auto* s0 = R.s[j];
        const auto* f0 = R.f[j];
        const auto* h0 = R.h[j];
        const auto* s1 = R.s[j + 1];
        const auto* f1 = R.f[j + 1];
        const auto* h1 = R.h[j + 1];
#if defined(__SSE4_1__)
        {  // both Gauss points at once (the same values and order as the loop below)
            typedef double D2 __attribute__((vector_size(16)));
            const D2 yy = D2{mid, mid} + D2{-g2, g2} * len;
            const D2 x = xa + (yy - ya) * k;
            const D2 fl = _mm_floor_pd(x);
            const D2 uf = _mm_min_pd(_mm_max_pd(fl, D2{0.0, 0.0}), D2{umax, umax});  // (NaN: 0)
            const D2 t = x - uf, ty = yy - n;
            const D2 w0 = g * (1.0 - ty), w1 = g * ty;
            const int64_t ua = int64_t(uf[0]), ub = int64_t(uf[1]);
            acc = acc + w0[0] * (s0[ua] + t[0] * (f0[ua] + t[0] * h0[ua]))
                      + w1[0] * (s1[ua] + t[0] * (f1[ua] + t[0] * h1[ua]))
                      + w0[1] * (s0[ub] + t[1] * (f0[ub] + t[1] * h0[ub]))
                      + w1[1] * (s1[ub] + t[1] * (f1[ub] + t[1] * h1[ub]));
        }
#else
        for (int p = 0; p < 2; ++p) {
            const double yy = p == 0 ? mid - g2 * len : mid + g2 * len;
            const double x = xa + (yy - ya) * k;
            const double uf = std::min(umax, std::max(0.0, bfloor(x)));
            const double t = x - uf, ty = yy - n;
            const int64_t u = int64_t(uf);
            acc = acc + (g * (1.0 - ty)) * (s0[u] + t * (f0[u] + t * h0[u]))
                      + (g * ty) * (s1[u] + t * (f1[u] + t * h1[u]));
        }
#endif
    }
}

// The directed edge from P to Q of a contour: + the integral of F dy from P to Q (edge_integral runs upwards, so
// an edge that runs down is integrated from Q to P and subtracted; a horizontal one adds nothing).
template <int NC, class RowsT>
inline void directed_edge(double px, double py, double qx, double qy, double umax, int64_t jmax, const RowsT& R,
                          typename Lanes<NC>::type& acc) {
    if (qy > py) edge_integral<NC>(px, py, qx, qy, 1.0, umax, jmax, R, acc);
    else edge_integral<NC>(qx, qy, px, py, -1.0, umax, jmax, R, acc);
}

// Twice the signed area of the quadrilateral V0 V1 V2 V3 (the shoelace formula): the sign of the contour
// integral of F dy around it, so that their ratio is the mean over it whichever way it turns.
inline double shoelace2(const double* vx, const double* vy) {
    return (vx[0] * vy[1] - vx[1] * vy[0]) + (vx[1] * vy[2] - vx[2] * vy[1]) + (vx[2] * vy[3] - vx[3] * vy[2])
           + (vx[3] * vy[0] - vx[0] * vy[3]);
}

// The bilinear reconstruction integrated over the parallelogram c + s a + r b (s, r in [-1/2, 1/2]) inside its
// window of nu x nv texels, into acc (c in window coordinates: texel (0, 0) at its first texel, where a
// footprint at 2^40 keeps the precision of its sides): by Green's theorem, the integral over y of F at the right
// ends of its rows less F at the left ends (F as in edge_integral), edge by edge. Returns the area.
template <int NC, class RowsT>
double prefix_slices(double cx, double cy, double ax, double ay, double bx, double by, int64_t nu, int64_t nv,
                     const RowsT& R, typename Lanes<NC>::type& acc) {
    const double vx[4] = {cx - 0.5 * ax - 0.5 * bx, cx + 0.5 * ax - 0.5 * bx, cx + 0.5 * ax + 0.5 * bx,
                          cx - 0.5 * ax + 0.5 * bx};
    const double vy[4] = {cy - 0.5 * ay - 0.5 * by, cy + 0.5 * ay - 0.5 * by, cy + 0.5 * ay + 0.5 * by,
                          cy - 0.5 * ay + 0.5 * by};
    // the lowest vertex B and the highest T are opposite; of the other two, L lies left of the line B T and R
    // right of it: the left ends run along B L and L T, the right ends along B R and R T
    int ib = 0;
    for (int e = 1; e < 4; ++e) ib = vy[e] < vy[ib] ? e : ib;
    const int it = (ib + 2) & 3, m1 = (ib + 1) & 3, m2 = (ib + 3) & 3;
    const double cross = (vx[m1] - vx[ib]) * (vy[it] - vy[ib]) - (vy[m1] - vy[ib]) * (vx[it] - vx[ib]);
    const int il = cross < 0.0 ? m1 : m2, ir = cross < 0.0 ? m2 : m1;
    const double umax = double(nu - 2);
    const int64_t jmax = nv - 2;
    edge_integral<NC>(vx[ib], vy[ib], vx[ir], vy[ir], 1.0, umax, jmax, R, acc);
    edge_integral<NC>(vx[ir], vy[ir], vx[it], vy[it], 1.0, umax, jmax, R, acc);
    edge_integral<NC>(vx[ib], vy[ib], vx[il], vy[il], -1.0, umax, jmax, R, acc);
    edge_integral<NC>(vx[il], vy[il], vx[it], vy[it], -1.0, umax, jmax, R, acc);
    return std::fabs(ax * by - ay * bx);
}

}  // namespace footprint_edges
}  // namespace lenslab
