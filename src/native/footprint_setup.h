// The footprint filter's setup of each footprint (src/native/footprint_runs.cpp): its pyramid level, its
// parallelogram (given a thickness when it is a line or a point), its window and slicing direction; and the side
// that neighbouring pixels of an output row share, which makes each a quadrilateral (NumPy reference:
// lenslab.warp.kernels.footprint_reference). Included by footprint_runs.cpp only.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "footprint_chunks.h"
#include "footprint_edges.h"
#include "kernels.h"

namespace lenslab {
// Internal linkage (an unnamed namespace: footprint_runs.cpp alone includes this), as when these were part of that
// file: the compiler builds the filter's loop to the same instructions (as inline functions of a named namespace,
// they changed its register allocation).
namespace {

using footprint_edges::clamp_side;
using footprint_edges::ifloor;
using footprint_edges::Span;
using footprint_edges::WINDOW;

constexpr double THIN = 1e-3;  // texels: a box narrower than this is read as a line (error ~THIN^2)

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

}  // namespace
}  // namespace lenslab
