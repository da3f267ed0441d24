// The map lattice's arithmetic (lenslab.warp.lattice): ghost nodes, Catmull-Rom coefficients per cell, and the
// band kernels that evaluate the map from them. Built without fused multiply-adds: the same bits as the NumPy
// reference (lenslab/warp/kernels/lattice_reference.py).
#include "lattice.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

namespace lenslab {

namespace {

// Catmull-Rom basis: weight_i(t) = sum_a CR[i][a] t^a (lenslab.warp.lattice.CR_BASIS)
constexpr double CR[4][4] = {{0.0, -0.5, 1.0, -0.5}, {1.0, 0.0, -2.5, 1.5}, {0.0, 0.5, 2.0, -1.5}, {0.0, 0.0, -0.5, 0.5}};

// min(max(int(floor(p)), 0), n - 1), NaN to 0, and no integer conversion of a value out of range
inline int64_t cell_of(double p, int64_t n) {
    if (!(p >= 0.0)) return 0;
    if (p >= double(n - 1)) return n - 1;
    return int64_t(p);
}

inline void cr_weights(double t, double* w) {
    const double t2 = t * t, t3 = t2 * t;
    w[0] = 0.5 * (-t3 + 2.0 * t2 - t);
    w[1] = 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0);
    w[2] = 0.5 * (-3.0 * t3 + 4.0 * t2 + t);
    w[3] = 0.5 * (t3 - t2);
}

// v unwrapped to within half a period of ref
inline double unwrap(double v, double ref, double wrap) { return v - wrap * std::floor((v - ref) / wrap + 0.5); }

inline double poly(const double* c, double tx, double ty) {  // c[b * 4 + a] of tx^a ty^b, Horner in both
    double acc = 0.0;
    for (int b = 3; b >= 0; --b)
        acc = acc * ty + (((c[b * 4 + 3] * tx + c[b * 4 + 2]) * tx + c[b * 4 + 1]) * tx + c[b * 4 + 0]);
    return acc;
}

inline void store_cell(const LatticeBand& b, int64_t at, int st, double x, double y, double dx, double dy, double dz) {
    if (st == 1) {
        b.xs[at] = float(x - 0.5);
        b.ys[at] = float(y - 0.5);
        b.valid[at] = true;
        b.need[at] = NEED_DONE;
        return;
    }
    b.xs[at] = 0.0f;
    b.ys[at] = 0.0f;
    b.valid[at] = false;
    if (st == 2) {
        b.dirs[3 * at] = dx;
        b.dirs[3 * at + 1] = dy;
        b.dirs[3 * at + 2] = dz;
        b.need[at] = NEED_PROJECT;
    } else {
        b.need[at] = st == 0 ? NEED_EXACT : NEED_DONE;
    }
}

}  // namespace

void ghost_pass(double* __restrict__ gx, double* __restrict__ gy, bool* __restrict__ have, int64_t rows, int64_t cols,
                double wrap) {
    std::vector<char> known(size_t(rows * cols));
    for (int axis = 1; axis >= 0; --axis) {
        for (int64_t q = 0; q < rows * cols; ++q) known[size_t(q)] = have[q];
        const int64_t n = axis == 1 ? cols : rows;
        const int64_t d = axis == 1 ? 1 : cols;  // flat distance of one node along the pass
        for (int step = 1; step >= -1; step -= 2) {
            for (int64_t a = 0; a < rows; ++a) {
                for (int64_t bb = 0; bb < cols; ++bb) {
                    const int64_t q = a * cols + bb;
                    if (have[q]) continue;
                    const int64_t k = axis == 1 ? bb : a;
                    if ((step == 1 && k < 3) || (step == -1 && k > n - 4)) continue;
                    const int64_t q1 = q - step * d, q2 = q - 2 * step * d, q3 = q - 3 * step * d;
                    if (!(known[size_t(q1)] && known[size_t(q2)])) continue;
                    const double x1 = gx[q1], y1 = gy[q1], y2 = gy[q2];
                    double x2 = gx[q2];
                    if (wrap > 0.0) x2 = x2 - wrap * std::nearbyint((x2 - x1) / wrap);  // np.round: half to even
                    if (known[size_t(q3)]) {
                        double x3 = gx[q3];
                        const double y3 = gy[q3];
                        if (wrap > 0.0) x3 = x3 - wrap * std::nearbyint((x3 - x1) / wrap);
                        gx[q] = 3.0 * x1 - 3.0 * x2 + x3;
                        gy[q] = 3.0 * y1 - 3.0 * y2 + y3;
                    } else {
                        gx[q] = 2.0 * x1 - x2;
                        gy[q] = 2.0 * y1 - y2;
                    }
                    have[q] = true;
                }
            }
        }
    }
}

namespace {

template <bool WRAP>
void grid_t(const double* __restrict__ nx, const double* __restrict__ ny, int64_t rows, int64_t cols, const double* wx,
            const double* wy, double wrap, double* __restrict__ ox, double* __restrict__ oy) {
    const int64_t ncy = rows - 3, ncx = cols - 3;
    for (int64_t cb = 0; cb < ncy; ++cb) {
        for (int64_t ca = 0; ca < ncx; ++ca) {  // vectorised across the cells of a row
            const double ref = nx[(cb + 1) * cols + ca + 1];
            double sx = 0.0, sy = 0.0;
            for (int j = 0; j < 4; ++j) {
                double rx = 0.0, ry = 0.0;
                for (int i = 0; i < 4; ++i) {
                    const int64_t q = (cb + j) * cols + ca + i;
                    double v = nx[q];
                    if (WRAP) v -= wrap * std::floor((v - ref) / wrap + 0.5);
                    rx += wx[i] * v;
                    ry += wx[i] * ny[q];
                }
                sx += wy[j] * rx;
                sy += wy[j] * ry;
            }
            ox[cb * ncx + ca] = sx;
            oy[cb * ncx + ca] = sy;
        }
    }
}

}  // namespace

void lattice_grid(const double* nx, const double* ny, int64_t rows, int64_t cols, double tx, double ty, double wrap,
                  double* ox, double* oy) {
    double wx[4], wy[4];
    cr_weights(tx, wx);
    cr_weights(ty, wy);
    if (wrap > 0.0) grid_t<true>(nx, ny, rows, cols, wx, wy, wrap, ox, oy);
    else grid_t<false>(nx, ny, rows, cols, wx, wy, wrap, ox, oy);
}

void cell_coefficients(const double* __restrict__ nodes, int64_t nk, const int8_t* __restrict__ state, int64_t ncy,
                       int64_t ncx, int64_t cb0, int64_t cb1, double wrap, double* __restrict__ coef) {
    const int64_t cols = ncx + 3, plane = (ncy + 3) * cols;
    double p[4][4], t[4][4];
    for (int64_t cb = cb0; cb < cb1; ++cb) {
        for (int64_t ca = 0; ca < ncx; ++ca) {
            const int st = state[cb * ncx + ca];
            if (st <= 0) continue;
            const int q0 = st == 1 ? 0 : 2, q1 = st == 1 ? 2 : 5;
            for (int q = q0; q < q1; ++q) {
                const double* nq = nodes + q * plane;
                const double ref = nq[(cb + 1) * cols + ca + 1];
                for (int j = 0; j < 4; ++j)
                    for (int i = 0; i < 4; ++i) {
                        double v = nq[(cb + j) * cols + ca + i];
                        if (q == 0 && wrap > 0.0) v -= wrap * std::floor((v - ref) / wrap + 0.5);
                        p[j][i] = v;
                    }
                for (int j = 0; j < 4; ++j)  // t = p CR, then c = CR^T t
                    for (int a = 0; a < 4; ++a) {
                        double acc = 0.0;
                        for (int i = 0; i < 4; ++i) acc += p[j][i] * CR[i][a];
                        t[j][a] = acc;
                    }
                double* c = coef + (((cb - cb0) * ncx + ca) * nk + q) * 16;
                for (int b = 0; b < 4; ++b)
                    for (int a = 0; a < 4; ++a) {
                        double acc = 0.0;
                        for (int j = 0; j < 4; ++j) acc += CR[j][b] * t[j][a];
                        c[b * 4 + a] = acc;
                    }
            }
        }
    }
}

void lattice_eval(const LatticeBand& b, double step) {
    const double inv = 1.0 / step;
    for (int64_t r = 0; r < b.h; ++r) {
        const int64_t ro = r % b.ho;
        for (int64_t c = 0; c < b.w; ++c) {
            const int64_t co = b.wo > 1 ? c : 0;
            for (int64_t k = 0; k < b.n; ++k) {
                const double* o = b.offs + ((ro * b.wo + co) * b.n + k) * 2;
                const double px = (double(c) + o[0]) * inv;
                const double py = (double(b.r0 + r) + o[1]) * inv;
                const int64_t ca = cell_of(std::floor(px), b.ncx), cb = cell_of(std::floor(py), b.ncy);
                const int st = b.state[cb * b.ncx + ca];
                const double tx = px - double(ca), ty = py - double(cb);
                const double* cf = b.coef + ((cb - b.cb0) * b.ncx + ca) * b.nk * 16;
                double x = 0.0, y = 0.0, dx = 0.0, dy = 0.0, dz = 0.0;
                if (st == 1) {
                    x = poly(cf, tx, ty);
                    y = poly(cf + 16, tx, ty);
                } else if (st == 2) {
                    dx = poly(cf + 32, tx, ty);
                    dy = poly(cf + 48, tx, ty);
                    dz = poly(cf + 64, tx, ty);
                }
                store_cell(b, (r * b.w + c) * b.n + k, st, x, y, dx, dy, dz);
            }
        }
    }
}

void lattice_rows(const LatticeBand& b, double inv) {
    double rc[5][4];
    const int64_t w = b.w, n = b.n;
    // the runs of samples k along a row that share a cell: the same in every row (they depend on the column
    // alone), so found once for the band
    struct Run { int64_t c, c1, ca; };
    std::vector<std::vector<Run>> runs(static_cast<size_t>(n));
    for (int64_t k = 0; k < n; ++k) {
        const double ox = b.offs[2 * k];
        int64_t c = 0;
        while (c < w) {
            const int64_t ca = cell_of(std::floor((double(c) + ox) * inv), b.ncx);
            int64_t c1 = w;  // the samples up to c1 share cell ca (the last cell: all)
            if (ca < b.ncx - 1) {
                const double edge = double(ca + 1);
                c1 = std::min(w, std::max(c + 1, int64_t(std::ceil(edge / inv - ox))));
                while (c1 > c + 1 && (double(c1 - 1) + ox) * inv >= edge) --c1;
                while (c1 < w && (double(c1) + ox) * inv < edge) ++c1;
            }
            runs[size_t(k)].push_back({c, c1, ca});
            c = c1;
        }
    }
    // one sample per pixel: each column's fraction in its cell, the same in every row
    std::vector<double> txs(n == 1 ? size_t(w) : 0);
    if (n == 1)
        for (const Run& run : runs[0])
            for (int64_t cc = run.c; cc < run.c1; ++cc) txs[size_t(cc)] = (double(cc) + b.offs[0]) * inv - double(run.ca);
    for (int64_t r = 0; r < b.h; ++r) {
        for (int64_t k = 0; k < n; ++k) {
            const double ox = b.offs[2 * k];
            const double py = (double(b.r0 + r) + b.offs[2 * k + 1]) * inv;
            const int64_t cb = cell_of(std::floor(py), b.ncy);
            const double ty = py - double(cb);
            float* xr = b.xs + r * w * n + k;  // the samples k of row r: stride n
            float* yr = b.ys + r * w * n + k;
            bool* vr = b.valid + r * w * n + k;
            int8_t* nr = b.need + r * w * n + k;
            const std::vector<Run>& row_runs = runs[size_t(k)];
            for (size_t i = 0; i < row_runs.size(); ++i) {
                const Run& run = row_runs[i];
                const int64_t c = run.c, ca = run.ca;
                int64_t c1 = run.c1;
                const int st = b.state[cb * b.ncx + ca];
                if (st < 0) {  // unseen (store_cell's values), with the unseen cells after it: one run to fill
                    while (i + 1 < row_runs.size() && b.state[cb * b.ncx + row_runs[i + 1].ca] < 0) c1 = row_runs[++i].c1;
                    if (n == 1) {  // contiguous: a photo's panorama is mostly such runs
                        std::fill(xr + c, xr + c1, 0.0f);
                        std::fill(yr + c, yr + c1, 0.0f);
                        std::memset(vr + c, 0, size_t(c1 - c));  // false
                        std::memset(nr + c, NEED_DONE, size_t(c1 - c));
                        continue;
                    }
                    for (int64_t cc = c; cc < c1; ++cc) {
                        xr[cc * n] = 0.0f;
                        yr[cc * n] = 0.0f;
                        vr[cc * n] = false;
                        nr[cc * n] = NEED_DONE;
                    }
                    continue;
                }
                const double* cf = b.coef + ((cb - b.cb0) * b.ncx + ca) * b.nk * 16;
                if (st > 0) {  // each component's bicubic along this row: a cubic in tx
                    const int q0 = st == 1 ? 0 : 2, q1 = st == 1 ? 2 : 5;
                    for (int q = q0; q < q1; ++q)
                        for (int a = 0; a < 4; ++a) {
                            const double* cq = cf + q * 16;
                            rc[q][a] = ((cq[12 + a] * ty + cq[8 + a]) * ty + cq[4 + a]) * ty + cq[a];
                        }
                }
                const double dca = double(ca);
                if (st == 1 && n == 1) {  // one sample per pixel: contiguous rows, the same arithmetic vectorised
                    const double a0 = rc[0][0], a1 = rc[0][1], a2 = rc[0][2], a3 = rc[0][3];
                    const double b0 = rc[1][0], b1 = rc[1][1], b2 = rc[1][2], b3 = rc[1][3];
                    float* __restrict__ xo = xr;
                    float* __restrict__ yo = yr;
                    const double* __restrict__ tr = txs.data();
                    for (int64_t cc = c; cc < c1; ++cc) {
                        const double tx = tr[cc];
                        xo[cc] = float((((a3 * tx + a2) * tx + a1) * tx + a0) - 0.5);
                        yo[cc] = float((((b3 * tx + b2) * tx + b1) * tx + b0) - 0.5);
                    }
                    for (int64_t cc = c; cc < c1; ++cc) {  // (a run is a cell's few samples: no call to memset)
                        vr[cc] = true;
                        nr[cc] = NEED_DONE;
                    }
                } else if (st == 1) {
                    const double a0 = rc[0][0], a1 = rc[0][1], a2 = rc[0][2], a3 = rc[0][3];
                    const double b0 = rc[1][0], b1 = rc[1][1], b2 = rc[1][2], b3 = rc[1][3];
                    for (int64_t cc = c; cc < c1; ++cc) {
                        const double tx = (double(cc) + ox) * inv - dca;
                        xr[cc * n] = float((((a3 * tx + a2) * tx + a1) * tx + a0) - 0.5);
                        yr[cc * n] = float((((b3 * tx + b2) * tx + b1) * tx + b0) - 0.5);
                        vr[cc * n] = true;
                        nr[cc * n] = NEED_DONE;
                    }
                } else {
                    for (int64_t cc = c; cc < c1; ++cc) {
                        const double tx = (double(cc) + ox) * inv - dca;
                        double dx = 0.0, dy = 0.0, dz = 0.0;
                        if (st == 2) {
                            dx = ((rc[2][3] * tx + rc[2][2]) * tx + rc[2][1]) * tx + rc[2][0];
                            dy = ((rc[3][3] * tx + rc[3][2]) * tx + rc[3][1]) * tx + rc[3][0];
                            dz = ((rc[4][3] * tx + rc[4][2]) * tx + rc[4][1]) * tx + rc[4][0];
                        }
                        store_cell(b, (r * w + cc) * n + k, st, 0.0, 0.0, dx, dy, dz);
                    }
                }
            }
        }
    }
}

void place(const int64_t* at, const double* xy, const bool* v, int64_t n, float* xs, float* ys, bool* valid) {
    for (int64_t e = 0; e < n; ++e) {
        const int64_t q = at[e];
        const bool ok = v[e];
        xs[q] = ok ? float(xy[2 * e] - 0.5) : 0.0f;
        ys[q] = ok ? float(xy[2 * e + 1] - 0.5) : 0.0f;
        valid[q] = ok;
    }
}

// The footprints (n, 4: a then b, float32) thinner than min(sqrt(h2), longer side / sqrt(q2)) across their longer
// side, their indices into idx; returns how many (lenslab.warp.antialias.thicken_slivers). Each step rounds to
// float32 as NumPy's does (this file is built without fused multiply-adds); NaN is not thin.
int64_t thin_footprints(const float* __restrict__ foot, int64_t n, float h2, float q2, int64_t* __restrict__ idx) {
    constexpr int64_t BLOCK = 256;  // the tests of a block at once (vectorised), then its thin ones listed
    uint8_t thin[BLOCK];
    int64_t k = 0;
    for (int64_t e0 = 0; e0 < n; e0 += BLOCK) {
        const int64_t m = std::min(BLOCK, n - e0);
        const float* f = foot + 4 * e0;
        uint8_t any = 0;
        for (int64_t e = 0; e < m; ++e) {
            const float a0 = f[4 * e], a1 = f[4 * e + 1], b0 = f[4 * e + 2], b1 = f[4 * e + 3];
            const float la = a0 * a0 + a1 * a1, lb = b0 * b0 + b1 * b1;
            const float long2 = la > lb ? la : lb;
            float cross = a0 * b1;
            cross -= a1 * b0;
            cross *= cross;
            // cross < min(long2 h2, long2^2 / q2), false where NumPy's maximum or minimum gives NaN (la or lb NaN;
            // the products of a long2 that is not NaN are not NaN)
            const uint8_t t = (la == la) & (lb == lb) & (cross < long2 * h2) & (cross < long2 * long2 / q2);
            thin[e] = t;
            any |= t;
        }
        if (!any) continue;
        for (int64_t e = 0; e < m; ++e) {
            idx[k] = e0 + e;
            k += thin[e];
        }
    }
    return k;
}

}  // namespace lenslab
