// The footprint prefilter: each output sample averages the bilinear source over its footprint, a
// parallelogram read from the finest pyramid level at which it spans at most max_taps texels (see
// lenslab/warp/antialias.py for the method). By Green's theorem, edge by edge: the integral over y of F at the
// right ends of the parallelogram's rows less F at the left ends, F the integral of the row's linear interpolant
// from the window's first texel (per-row prefix sums of the window: O(1) per point, whatever the width), each
// edge cut at the texel rows and integrated by 2-point Gauss-Legendre. In float64, in the order of the NumPy
// reference (lenslab.warp.kernels.reference.prefix_slices); a footprint clipped by its window (beyond the
// coarsest level) takes the texel weights of the slices instead (reference.slice_weights). The edge integrals
// are in footprint_edges.h. The footprints of a run of pixels in an output row share one window
// (footprint_chunks.h), and neighbouring pixels of a row share the side between them: a quadrilateral whose
// shared side is integrated once for both (reference.footprint with rows of pixels).
#include <algorithm>
#include <climits>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include "bind.h"
#include "footprint_chunks.h"
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

// A sample's footprint as the filter reads it: mode 0 not read, 1 inside its window (the rows' prefix sums), 2
// clipped by its window (beyond the coarsest level: the texels' weights)
struct Item {
    int mode;
    bool cols;  // sliced along columns (x and y swap roles)
    bool thin;  // given a thickness (a line or a point)
    bool sl, sr;  // its left (-a) or right (+a) side is the one shared with that neighbour (a quadrilateral)
    bool seam;  // its left neighbour lies a turn away (across the seam): their windows' rows do not line up
    int64_t lev, wx0, wy0, nwx, nwy;
    double cx, cy, tax, tay, tbx, tby;
    double qx[4], qy[4];  // a quadrilateral's vertices V0 (-a -b) V1 (+a -b) V2 (+a +b) V3 (-a +b), from c
    double long2, area2;  // the (thickened) parallelogram's longer side and area, squared (within)
    Span w;  // the window in slice coordinates (mode 1)
};

__attribute__((always_inline)) inline void setup(Item& it, const int64_t* shapes, int64_t nlev, double h0, float xs,
                                                 float ys, const float* f, double max_taps) {
    it.mode = 1;
    const double fax = clamp_side(f[0]), fay = clamp_side(f[1]), fbx = clamp_side(f[2]), fby = clamp_side(f[3]);
    const double la = fax * fax + fay * fay, lb = fbx * fbx + fby * fby;
    int64_t lev = 0;
    if (std::max(la, lb) > max_taps * max_taps) {  // beyond level 0 (the square roots only then)
        const double longest = std::max(std::sqrt(la), std::sqrt(lb));
        while (lev + 1 < nlev && longest > max_taps * double(int64_t(1) << lev)) ++lev;
    }
    it.lev = lev;
    const double scale = lev == 0 ? 1.0 : double(shapes[2 * lev]) / h0;  // (level 0: exactly 1)
    const double ax = fax * scale, ay = fay * scale, bx = fbx * scale, by = fby * scale;
    it.cx = (double(clamp_pos(xs)) + 0.5) * scale - 0.5;  // NaN: the left or top edge
    it.cy = (double(clamp_pos(ys)) + 0.5) * scale - 0.5;
    // a degenerate footprint (a line or a point) gets a thickness far below a texel
    double tax = ax, tay = ay, tbx = bx, tby = by;
    it.thin = !(std::fabs(ax * by - ay * bx) >= THIN * THIN);
    it.sl = it.sr = it.seam = false;
    if (it.thin) {
        const double la = std::hypot(ax, ay), lb = std::hypot(bx, by);
        if (la >= lb && la > 0.0) { tbx = -THIN * ay / la; tby = THIN * ax / la; }
        else if (lb > 0.0) { tax = THIN * by / lb; tay = -THIN * bx / lb; }
        else { tax = THIN; tay = 0.0; tbx = 0.0; tby = THIN; }
    }
    it.tax = tax; it.tay = tay; it.tbx = tbx; it.tby = tby;
    {
        const double la = tax * tax + tay * tay, lb = tbx * tbx + tby * tby, area = tax * tby - tay * tbx;
        it.long2 = std::max(la, lb);
        it.area2 = area * area;
    }
    // the window: every texel the reconstruction over the (thickened) parallelogram touches
    const double ex = 0.5 * (std::fabs(tax) + std::fabs(tbx)) + 1.0, ey = 0.5 * (std::fabs(tay) + std::fabs(tby)) + 1.0;
    it.wx0 = ifloor(it.cx - ex) + 1;
    it.wy0 = ifloor(it.cy - ey) + 1;
    it.nwx = ifloor(it.cx + ex) + 1 - it.wx0;
    it.nwy = ifloor(it.cy + ey) + 1 - it.wy0;
    // a footprint beyond the coarsest level: the window is centred on it (its top-left corner may miss a
    // rotated footprint entirely: no weight at all, and 0 / 0)
    if (it.nwx > WINDOW) { it.wx0 = ifloor(it.cx) + 1 - WINDOW / 2; it.nwx = WINDOW; }
    if (it.nwy > WINDOW) { it.wy0 = ifloor(it.cy) + 1 - WINDOW / 2; it.nwy = WINDOW; }
    it.cols = ey > ex;  // slice along the shorter extent (fewer slices): along columns if x is
    if (!(it.nwx < WINDOW && it.nwy < WINDOW)) it.mode = 2;
    it.w = it.cols ? Span{it.wy0, it.wx0, it.nwy, it.nwx} : Span{it.wx0, it.wy0, it.nwx, it.nwy};
}

// Neighbouring pixels of an output row share the side between them (their footprints' sides there, averaged), so
// that their footprints tile the row and one integral along it serves both. Only parallelograms sliced along rows
// with room in their window, of one level, whose sides there lie within an eighth of their smaller height of each
// other (not across a piece's edge or a fold of the map; across the seam, a turn apart).
inline bool shareable(const Item& it) {
    return it.mode == 1 && !it.cols && !it.thin && it.nwx <= WINDOW - 3 && it.nwy <= WINDOW - 3;
}

// whether gap is within an eighth of the parallelogram's smaller height (its area over its longer side), squared:
// (8 gap)^2 |longer side|^2 <= area^2
__attribute__((always_inline)) inline bool within(double gap, const Item& it) {
    const double g8 = 8.0 * gap;
    return g8 * g8 * it.long2 <= it.area2;
}

// (period: the level's width when the source wraps around, else 0)
__attribute__((always_inline)) inline void link(Item& l, Item& r, const int64_t* shapes, bool wrap) {
    if (!shareable(l) || !shareable(r) || l.lev != r.lev) return;
    double dx = r.cx - l.cx;
    const double dy = r.cy - l.cy;
    double turns = 0.0;
    if (wrap) {  // neighbours across the seam: r's centre a turn nearer
        const double period = double(shapes[2 * l.lev + 1]);
        turns = std::nearbyint(dx / period);
        dx -= period * turns;
    }
    // l's V1 and V2, r's V0 and V3, from l's centre
    const double l1x = 0.5 * l.tax - 0.5 * l.tbx, l1y = 0.5 * l.tay - 0.5 * l.tby;
    const double l2x = 0.5 * l.tax + 0.5 * l.tbx, l2y = 0.5 * l.tay + 0.5 * l.tby;
    const double r0x = dx + (-0.5 * r.tax - 0.5 * r.tbx), r0y = dy + (-0.5 * r.tay - 0.5 * r.tby);
    const double r3x = dx + (-0.5 * r.tax + 0.5 * r.tbx), r3y = dy + (-0.5 * r.tay + 0.5 * r.tby);
    const double gap = std::max(std::max(std::fabs(l1x - r0x), std::fabs(l1y - r0y)),
                                std::max(std::fabs(l2x - r3x), std::fabs(l2y - r3y)));
    // within an eighth of the footprints' smaller height (a sliver's sides may not move by more than a little of
    // its thickness)
    if (!(within(gap, l) && within(gap, r))) return;  // (NaN: not shared)
    const double p1x = 0.5 * (l1x + r0x), p1y = 0.5 * (l1y + r0y), p2x = 0.5 * (l2x + r3x), p2y = 0.5 * (l2y + r3y);
    l.sr = r.sl = true;
    r.seam = turns != 0.0;
    l.qx[1] = p1x; l.qy[1] = p1y; l.qx[2] = p2x; l.qy[2] = p2y;
    r.qx[0] = p1x - dx; r.qy[0] = p1y - dy; r.qx[3] = p2x - dx; r.qy[3] = p2y - dy;
}

// A footprint with a shared side: its own vertices on the other sides, and the window of the quadrilateral.
__attribute__((always_inline)) inline void finish_quad(Item& it) {
    if (!it.sl && !it.sr) return;
    if (!it.sl) {
        it.qx[0] = -0.5 * it.tax - 0.5 * it.tbx; it.qy[0] = -0.5 * it.tay - 0.5 * it.tby;
        it.qx[3] = -0.5 * it.tax + 0.5 * it.tbx; it.qy[3] = -0.5 * it.tay + 0.5 * it.tby;
    }
    if (!it.sr) {
        it.qx[1] = 0.5 * it.tax - 0.5 * it.tbx; it.qy[1] = 0.5 * it.tay - 0.5 * it.tby;
        it.qx[2] = 0.5 * it.tax + 0.5 * it.tbx; it.qy[2] = 0.5 * it.tay + 0.5 * it.tby;
    }
    const double x0 = std::min(std::min(it.qx[0], it.qx[1]), std::min(it.qx[2], it.qx[3]));
    const double x1 = std::max(std::max(it.qx[0], it.qx[1]), std::max(it.qx[2], it.qx[3]));
    const double y0 = std::min(std::min(it.qy[0], it.qy[1]), std::min(it.qy[2], it.qy[3]));
    const double y1 = std::max(std::max(it.qy[0], it.qy[1]), std::max(it.qy[2], it.qy[3]));
    // every texel the reconstruction over it touches: floor(x) and floor(x) + 1 for each x it spans
    it.wx0 = ifloor(it.cx + x0);
    it.wy0 = ifloor(it.cy + y0);
    it.nwx = ifloor(it.cx + x1) + 2 - it.wx0;
    it.nwy = ifloor(it.cy + y1) + 2 - it.wy0;
    it.w = Span{it.wx0, it.wy0, it.nwx, it.nwy};
}

// NC > 0: that many channels, known to the compiler; NC == 0: nc (<= 64) at run time. The samples are read in
// chunks of CHUNK consecutive samples of one row of row_len (a multiple of ns); the footprints of a chunk at one
// level and slicing direction share windows (footprint_chunks.h), so a sample's value depends on its row alone,
// not on how the rows are split into bands.
template <int NC>
void footprint_t(const float* __restrict__ level0, const float* __restrict__ rest, const int64_t* shapes,
                 const int64_t* offsets, int64_t nlev, int64_t nc_, const float* __restrict__ xs,
                 const float* __restrict__ ys, const bool* __restrict__ valid, const float* __restrict__ foot,
                 int64_t npix, int64_t ns, int64_t row_len, Border b, double max_taps, float* __restrict__ out,
                 float* __restrict__ alpha) {
    typedef typename Lanes<NC>::type L;
    const int64_t nc = NC > 0 ? NC : nc_;
    const double inv = 1.0 / double(ns);
    const double h0 = double(shapes[0]);
    double wgt[(WINDOW + 2) * STRIDE];
    std::vector<Ragged<NC>> shared_buf(1);  // (the shared window's rows: on the heap)
    Ragged<NC>& G = shared_buf[0];
    RowPtrs<NC> R;
    Item items_buf[2][CHUNK];
    int cur = 0;
    int64_t next_c = -1;
    // the footprints of the chunk at c (in a row ending at end), their windows' texels prefetched
    // rows of pixels (one sample each): neighbours share sides
    const bool share = ns == 1 && row_len > 1;
    auto one = [&](int64_t s, Item& it) {
        if (!valid[s]) it.mode = 0;
        else setup(it, shapes, nlev, h0, xs[s], ys[s], foot + 4 * s, max_taps);
    };
    auto prepare = [&](int64_t c, int64_t end, Item* its) {
        const int n = int(std::min<int64_t>(CHUNK, end - c));
        for (int k = 0; k < n; ++k) one(c + k, its[k]);
        if (share) {  // the sides shared with the neighbours, the one before and the one after the chunk included
            const int64_t row0 = c - (c % row_len);
            Item before, after;
            before.mode = after.mode = 0;
            if (c > row0) one(c - 1, before);
            if (c + n < row0 + row_len) one(c + n, after);
            link(before, its[0], shapes, b.wrap);
            for (int k = 0; k + 1 < n; ++k) link(its[k], its[k + 1], shapes, b.wrap);
            link(its[n - 1], after, shapes, b.wrap);
            for (int k = 0; k < n; ++k) finish_quad(its[k]);
        }
        // the texels of the level-0 windows' bounding box, a cache line at a time (any other: window by window)
        const int64_t lh0 = shapes[0], lw0 = shapes[1];
        int64_t x0 = INT64_MAX, x1 = INT64_MIN, y0 = INT64_MAX, y1 = INT64_MIN;
        for (int k = 0; k < n; ++k) {
            const Item& it = its[k];
            if (it.mode != 1) continue;
            if (it.lev == 0) {
                x0 = std::min(x0, it.wx0); x1 = std::max(x1, it.wx0 + it.nwx);
                y0 = std::min(y0, it.wy0); y1 = std::max(y1, it.wy0 + it.nwy);
                continue;
            }
            const int64_t lh = shapes[2 * it.lev], lw = shapes[2 * it.lev + 1];
            const float* lbuf = rest + offsets[it.lev];
            const int64_t a = std::max<int64_t>(0, std::min(lw - 1, it.wx0));
            const int64_t e = std::max<int64_t>(0, std::min(lw - 1, it.wx0 + it.nwx - 1));
            for (int64_t y = std::max<int64_t>(0, it.wy0); y < std::min(lh, it.wy0 + it.nwy); ++y) {
                __builtin_prefetch(lbuf + (y * lw + a) * nc);
                __builtin_prefetch(lbuf + (y * lw + e) * nc + nc - 1);
            }
        }
        if (x0 < x1) {
            x0 = std::max<int64_t>(0, x0); x1 = std::min(lw0, x1);
            y0 = std::max<int64_t>(0, y0); y1 = std::min(lh0, y1);
            if (x0 < x1 && y0 < y1 && (x1 - x0) * (y1 - y0) <= CAP)
                for (int64_t y = y0; y < y1; ++y) {
                    const float* r = level0 + (y * lw0) * nc;
                    for (int64_t i = x0 * nc; i < x1 * nc; i += 16) __builtin_prefetch(r + i);
                    __builtin_prefetch(r + x1 * nc - 1);
                }
        }
    };
    int members[CHUNK];
    bool done[CHUNK];
    std::vector<double> val(size_t(CHUNK * nc));
    double acc[NC > 0 ? NC : 64];
    for (int64_t ch = 0; ch < nc; ++ch) acc[ch] = 0.0;
    int64_t hits = 0, sub = 0, q = 0;  // the samples of pixel q summed so far
    const int64_t total = npix * ns;
    for (int64_t row = 0; row < total; row += row_len) {
        const int64_t row_end = std::min(total, row + row_len);
        for (int64_t c = row; c < row_end; c += CHUNK) {
            const int n = int(std::min<int64_t>(CHUNK, row_end - c));
            if (c != next_c) prepare(c, row_end, items_buf[cur]);
            Item* items = items_buf[cur];
            // the next chunk's footprints now, and their texels fetched into the cache while this one is integrated
            next_c = c + n < row_end ? c + n : row_end < total ? row_end : -1;
            if (next_c >= 0) prepare(next_c, next_c == row_end ? std::min(total, row_end + row_len) : row_end,
                                     items_buf[1 - cur]);
            cur = 1 - cur;
            for (int k = 0; k < n; ++k) done[k] = items[k].mode == 0;
            for (int k = 0; k < n; ++k) {
                if (done[k]) continue;
                const Item& it = items[k];
                const float* lbuf = (it.lev == 0 ? level0 : rest) + offsets[it.lev];
                const int64_t lh = shapes[2 * it.lev], lw = shapes[2 * it.lev + 1];
                double* v = val.data() + k * nc;
                if (it.mode == 2) {  // a footprint beyond the coarsest level, clipped by its window: the texels' weights
                    done[k] = true;
                    const int64_t nu = it.cols ? it.nwy : it.nwx, nv = it.cols ? it.nwx : it.nwy;
                    double* const w = wgt + STRIDE;  // row -1 of the weights is scratch
                    for (int64_t j = 0; j < nv + 2; ++j) std::fill(wgt + j * STRIDE, wgt + j * STRIDE + nu + LANES, 0.0);
                    if (it.cols) slice_weights(it.cy, it.cx, it.tay, it.tax, it.tby, it.tbx, it.wy0, it.wx0, nu, nv, w, STRIDE);
                    else slice_weights(it.cx, it.cy, it.tax, it.tay, it.tbx, it.tby, it.wx0, it.wy0, nu, nv, w, STRIDE);
                    double part[NC > 0 ? NC : 64];
                    for (int64_t ch = 0; ch < nc; ++ch) part[ch] = 0.0;
                    if (it.cols) gather<NC, true>(lbuf, lw, lh, nc, b, it.wx0, it.wy0, it.nwx, it.nwy, w, STRIDE, part);
                    else gather<NC, false>(lbuf, lw, lh, nc, b, it.wx0, it.wy0, it.nwx, it.nwy, w, STRIDE, part);
                    double sum = 0.0;  // some weights clipped: their sum, not the area
                    for (int64_t j = 0; j < nv; ++j)
                        for (int64_t i = 0; i < nu; ++i) sum += w[j * STRIDE + i];
                    const double norm = 1.0 / sum;
                    for (int64_t ch = 0; ch < nc; ++ch) v[ch] = part[ch] * norm;
                    continue;
                }
                // a shared window: this footprint and the later ones of the chunk at its level and slicing direction
                // whose windows fit with it
                int nm = 0;
                members[nm++] = k;
                done[k] = true;
                int64_t u0 = it.w.u0, u1 = it.w.u0 + it.w.nu, v0 = it.w.v0, v1 = it.w.v0 + it.w.nv;
                for (int k2 = k + 1; k2 < n; ++k2) {
                    const Item& o = items[k2];
                    if (done[k2] || o.mode != 1 || o.lev != it.lev || o.cols != it.cols) continue;
                    const int64_t a0 = std::min(u0, o.w.u0), a1 = std::max(u1, o.w.u0 + o.w.nu);
                    const int64_t b0 = std::min(v0, o.w.v0), b1 = std::max(v1, o.w.v0 + o.w.nv);
                    if (b1 - b0 > MAXR || (a1 - a0) * (b1 - b0) > CAP) continue;  // (a seam, a jump of the map)
                    u0 = a0; u1 = a1; v0 = b0; v1 = b1;
                    members[nm++] = k2;
                    done[k2] = true;
                }
                G.start(v0, v1);
                for (int m = 0; m < nm; ++m) G.add(items[members[m]].w);
                constexpr int64_t GROUP = NC > 0 ? NC : 4;  // channels integrated at once
                for (int64_t c0 = 0; c0 < nc; c0 += GROUP) {
                    const int64_t cn = std::min(GROUP, nc - c0);
                    const bool finite = G.load(lbuf, lw, lh, nc, c0, cn, b, it.cols);
                    L carry{};  // the shared side of the last footprint, integrated from its frame (negated)
                    for (int m = 0; m < nm; ++m) {
                        const Item& o = items[members[m]];
                        if (!finite && nm > 1) {  // a texel not finite: this footprint through its own window alone
                            G.start(o.w.v0, o.w.v0 + o.w.nv);
                            G.add(o.w);
                            G.load(lbuf, lw, lh, nc, c0, cn, b, it.cols);
                        }
                        // the mean part * norm, within the texels the window read (where they are finite)
                        auto put = [&](const L& part, double norm) {
                            const L v = clamp_mean(part * norm, G.vmin, G.vmax);
                            double* vm = val.data() + members[m] * nc;
                            if constexpr (NC == 1) vm[0] = v;
                            else for (int64_t ch = 0; ch < cn; ++ch) vm[c0 + ch] = v[ch];
                        };
                        G.rows(o.w, R);
                        L part{};
                        if (o.sl || o.sr) {  // a quadrilateral: the contour V0 V1 V2 V3
                            double vx[4], vy[4];
                            for (int e = 0; e < 4; ++e) {
                                vx[e] = (o.cx - double(o.wx0)) + o.qx[e];
                                vy[e] = (o.cy - double(o.wy0)) + o.qy[e];
                            }
                            const double umax = double(o.w.nu - 2);
                            const int64_t jmax = o.w.nv - 2;
                            // its left side from the footprint before, when that one was just integrated
                            const bool have = o.sl && !o.seam && finite && m > 0 && members[m - 1] == members[m] - 1;
                            if (have) part = carry;
                            else directed_edge<NC>(vx[3], vy[3], vx[0], vy[0], umax, jmax, R, part);
                            directed_edge<NC>(vx[0], vy[0], vx[1], vy[1], umax, jmax, R, part);
                            directed_edge<NC>(vx[2], vy[2], vx[3], vy[3], umax, jmax, R, part);
                            L right{};
                            directed_edge<NC>(vx[1], vy[1], vx[2], vy[2], umax, jmax, R, right);
                            part = part + right;
                            carry = -right;
                            put(part, 2.0 / shoelace2(vx, vy));
                            continue;
                        }
                        const double area = o.cols ? prefix_slices<NC>(o.cy - double(o.wy0), o.cx - double(o.wx0), o.tay, o.tax,
                                                                       o.tby, o.tbx, o.w.nu, o.w.nv, R, part)
                                                   : prefix_slices<NC>(o.cx - double(o.wx0), o.cy - double(o.wy0), o.tax, o.tay,
                                                                       o.tbx, o.tby, o.w.nu, o.w.nv, R, part);
                        put(part, 1.0 / area);
                    }
                }
            }
            // the pixels' sums, in the samples' order
            for (int k = 0; k < n; ++k) {
                if (items[k].mode != 0) {
                    ++hits;
                    for (int64_t ch = 0; ch < nc; ++ch) acc[ch] += val[k * nc + ch];
                }
                if (++sub == ns) {  // the pixel's last sample
                    for (int64_t ch = 0; ch < nc; ++ch) { out[q * nc + ch] = float(acc[ch] * inv); acc[ch] = 0.0; }
                    alpha[q] = float(double(hits) * inv);
                    hits = 0;
                    sub = 0;
                    ++q;
                }
            }
        }
    }
}

}  // namespace

void footprint(const float* level0, const float* rest, const int64_t* shapes, const int64_t* offsets, int64_t nlev,
               int64_t nc, const float* xs, const float* ys, const bool* valid, const float* foot, int64_t npix,
               int64_t ns, int64_t row_len, Border b, double max_taps, float* out, float* alpha) {
    if (row_len <= 0 || row_len % ns != 0) row_len = ns;
    switch (nc) {
        case 1: return footprint_t<1>(level0, rest, shapes, offsets, nlev, nc, xs, ys, valid, foot, npix, ns, row_len, b, max_taps, out, alpha);
        case 3: return footprint_t<3>(level0, rest, shapes, offsets, nlev, nc, xs, ys, valid, foot, npix, ns, row_len, b, max_taps, out, alpha);
        case 4: return footprint_t<4>(level0, rest, shapes, offsets, nlev, nc, xs, ys, valid, foot, npix, ns, row_len, b, max_taps, out, alpha);
        default: return footprint_t<0>(level0, rest, shapes, offsets, nlev, nc, xs, ys, valid, foot, npix, ns, row_len, b, max_taps, out, alpha);
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
        // an output row: xs (rows, width, ns) holds rows of width * ns samples; any other shape, one pixel
        const int64_t row_len = xs.ndim() == 3 && int64_t(xs.shape(2)) == int64_t(ns)
                                    ? int64_t(xs.shape(1)) * int64_t(ns) : int64_t(ns);
        {
            nb::gil_scoped_release release;
            footprint(level0.data(), rest.data(), shapes.data(), offsets.data(), int64_t(shapes.shape(0)), nc,
                      xs.data(), ys.data(), valid.data(), foot.data(), int64_t(npix), int64_t(ns), row_len,
                      {wrap, top, bottom}, max_taps, out.data(), alpha.data());
        }
    }, nb::arg("level0"), nb::arg("rest"), nb::arg("shapes"), nb::arg("offsets"), nb::arg("xs"), nb::arg("ys"),
       nb::arg("valid"), nb::arg("foot"), nb::arg("wrap"), nb::arg("top"), nb::arg("bottom"), nb::arg("max_taps"),
       nb::arg("out").noconvert(), nb::arg("alpha").noconvert());
}
