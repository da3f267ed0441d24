// The separable samplers (lenslab.warp.filters): nearest, tent, Catmull-Rom and Lanczos-3 weights in float64
// from the exact position, every tap folded across the seam, the poles or into the neighbouring piece (a cube
// face across its edge). Built without fused multiply-adds: the bits of the NumPy reference
// (lenslab/warp/kernels/reference.py), but for the Lanczos sines, which libm and NumPy may round differently.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <vector>

#include "kernels.h"
#include "lattice.h"

namespace lenslab {

namespace {

constexpr double PI = 3.141592653589793;

inline double weight(int kind, double t) {
    const double a = std::fabs(t);
    if (kind == 1) return 1.0 - a > 0.0 ? 1.0 - a : 0.0;
    if (kind == 2) {
        if (a < 1.0) return (1.5 * a - 2.5) * a * a + 1.0;
        if (a < 2.0) return ((-0.5 * a + 2.5) * a - 4.0) * a + 2.0;
        return 0.0;
    }
    if (a == 0.0) return 1.0;
    if (a >= 3.0) return 0.0;
    const double pa = PI * a;
    return 3.0 * std::sin(pa) * std::sin(pa / 3.0) / (pa * pa);
}

inline int64_t piece_at(double x, double y, const Pieces& pc) {
    const double fc = std::floor((x + 0.5) / double(pc.cw)), fr = std::floor((y + 0.5) / double(pc.ch));
    if (!(fc >= 0.0 && fr >= 0.0 && fc < double(pc.gc) && fr < double(pc.gr))) return -1;
    return pc.grid[int64_t(fr) * pc.gc + int64_t(fc)];
}

}  // namespace

void fold_piece(int64_t& i, int64_t& j, int64_t p, const int64_t* table) {
    const int64_t* tp = table + p * 16;
    const int64_t x0 = tp[0], y0 = tp[1], pw = tp[2], ph = tp[3];
    const int64_t li = i - x0, lj = j - y0;
    if (li >= 0 && lj >= 0 && li < pw && lj < ph) return;
    const int64_t ex = li < 0 ? -1 - li : li - pw, ey = lj < 0 ? -1 - lj : lj - ph;
    int edge;
    int64_t k, s;
    if (ex >= ey) {
        edge = li < 0 ? 0 : 1;
        k = ex;
        s = std::min(std::max(lj, int64_t(0)), ph - 1);
    } else {
        edge = lj < 0 ? 2 : 3;
        k = ey;
        s = std::min(std::max(li, int64_t(0)), pw - 1);
    }
    const int64_t q = tp[4 + 3 * edge];
    if (q < 0) {  // nothing across: clamp into the piece
        i = std::min(std::max(i, x0), x0 + pw - 1);
        j = std::min(std::max(j, y0), y0 + ph - 1);
        return;
    }
    const int64_t e2 = tp[5 + 3 * edge];
    const int64_t* tq = table + q * 16;
    const int64_t qw = tq[2], qh = tq[3];
    const int64_t n = e2 < 2 ? qh : qw;
    if (tp[6 + 3 * edge]) s = (edge < 2 ? ph : pw) - 1 - s;
    s = std::min(std::max(s, int64_t(0)), n - 1);
    k = std::min(k, (e2 < 2 ? qw : qh) - 1);
    if (e2 == 0) { i = tq[0] + k; j = tq[1] + s; }
    else if (e2 == 1) { i = tq[0] + qw - 1 - k; j = tq[1] + s; }
    else if (e2 == 2) { i = tq[0] + s; j = tq[1] + k; }
    else { i = tq[0] + s; j = tq[1] + qh - 1 - k; }
}

void separable(const float* src, int64_t sw, int64_t sh, int64_t nc, const float* xs, const float* ys,
               const bool* valid, int64_t npix, int64_t ns, bool wrap, bool top, bool bottom, const Pieces& pc,
               int kind, float* out, float* alpha) {
    const double inv = 1.0 / double(ns);
    const int rad = std::max(kind, 1);
    std::vector<double> acc(static_cast<size_t>(nc));
    double wx[6], wy[6];
    auto fold = [&](int64_t& i, int64_t& j, int64_t piece) {
        if (piece >= 0) fold_piece(i, j, piece, pc.table);
        else fold_index(i, j, sw, sh, wrap, top, bottom);
    };
    for (int64_t q = 0; q < npix; ++q) {
        std::fill(acc.begin(), acc.end(), 0.0);
        int64_t hits = 0;
        for (int64_t k = q * ns; k < (q + 1) * ns; ++k) {
            if (!valid[k]) continue;
            ++hits;
            const double x = double(clamp_pos(xs[k])), y = double(clamp_pos(ys[k]));  // NaN: -2^40
            const int64_t piece = pc.np > 0 ? piece_at(x, y, pc) : -1;
            if (kind == 0) {
                int64_t ii = int64_t(std::floor(x + 0.5)), jj = int64_t(std::floor(y + 0.5));
                fold(ii, jj, piece);
                const float* px = src + (jj * sw + ii) * nc;
                for (int64_t c = 0; c < nc; ++c) acc[size_t(c)] += px[c];
                continue;
            }
            const int64_t i0 = int64_t(std::floor(x)), j0 = int64_t(std::floor(y));
            double sx = 0.0, sy = 0.0;
            for (int t = 0; t < 2 * rad; ++t) {
                wx[t] = weight(kind, x - double(i0 - rad + 1 + t));
                wy[t] = weight(kind, y - double(j0 - rad + 1 + t));
                sx += wx[t];
                sy += wy[t];
            }
            for (int tj = 0; tj < 2 * rad; ++tj) {
                if (wy[tj] == 0.0) continue;
                for (int ti = 0; ti < 2 * rad; ++ti) {
                    double ww = wx[ti] * wy[tj];
                    if (ww == 0.0) continue;
                    ww /= sx * sy;
                    int64_t ii = i0 - rad + 1 + ti, jj = j0 - rad + 1 + tj;
                    fold(ii, jj, piece);
                    const float* px = src + (jj * sw + ii) * nc;
                    for (int64_t c = 0; c < nc; ++c) acc[size_t(c)] += ww * double(px[c]);
                }
            }
        }
        for (int64_t c = 0; c < nc; ++c) {  // negative lobes overshoot: a finite source stays finite
            const double v = acc[size_t(c)] * inv;
            out[q * nc + c] = float(v > FLT_MAX ? double(FLT_MAX) : (v < -FLT_MAX ? -double(FLT_MAX) : v));
        }
        alpha[q] = float(double(hits) * inv);
    }
}

}  // namespace lenslab
