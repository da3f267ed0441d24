// Footprint sides of one-sample pixels from their neighbours' map positions (lenslab.warp.antialias):
// central differences, one-sided beside an invalid neighbour, the image's edge or a piece's seam.
#include <cmath>

#include "sampler.h"

namespace lenslab {

void neighbour_secants(const float* xs, const float* ys, const bool* vs, int64_t nrows, int64_t w, int64_t top,
                       int64_t h, double wrap, const int32_t* piece, float* foot, bool* edge) {
    for (int64_t r = 0; r < h; ++r) {
        const int64_t rr = r + top;
        for (int64_t c = 0; c < w; ++c) {
            const bool v0 = vs[rr * w + c];
            bool on_edge = false;
            for (int axis = 0; axis < 2; ++axis) {
                bool lo_ok, hi_ok;
                int64_t lo, hi;  // flat indices of the neighbours before and after along this axis
                if (axis == 0) {
                    lo_ok = c > 0;
                    hi_ok = c + 1 < w;
                    lo = rr * w + c - 1;
                    hi = rr * w + c + 1;
                } else {
                    lo_ok = rr > 0;
                    hi_ok = rr + 1 < nrows;
                    lo = (rr - 1) * w + c;
                    hi = (rr + 1) * w + c;
                }
                const int64_t me = rr * w + c;
                if (piece != nullptr) {  // a neighbour in another piece is beyond a seam: it does not count
                    lo_ok = lo_ok && piece[lo] == piece[me];
                    hi_ok = hi_ok && piece[hi] == piece[me];
                }
                const bool vl = lo_ok && vs[lo], vh = hi_ok && vs[hi];
                if ((lo_ok && vs[lo] != v0) || (hi_ok && vs[hi] != v0)) on_edge = true;
                double half = 1.0, dx = 0.0, dy = 0.0;
                if (vl && vh) {
                    dx = double(xs[hi] - xs[lo]);
                    dy = double(ys[hi] - ys[lo]);
                    half = 0.5;
                } else if (vh && v0) {
                    dx = double(xs[hi] - xs[me]);
                    dy = double(ys[hi] - ys[me]);
                } else if (vl && v0) {
                    dx = double(xs[me] - xs[lo]);
                    dy = double(ys[me] - ys[lo]);
                }
                if (wrap > 0.0) {  // unwrapped before halving: a difference across the seam is near +-wrap
                    const double turns = std::floor(dx / wrap + 0.5);
                    dx -= wrap * turns;
                }
                foot[(r * w + c) * 4 + 2 * axis] = float(half * dx);
                foot[(r * w + c) * 4 + 2 * axis + 1] = float(half * dy);
            }
            edge[r * w + c] = on_edge;
        }
    }
}

}  // namespace lenslab
