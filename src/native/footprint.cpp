// The footprint prefilter: each output sample averages the bilinear source over its footprint, read from
// the finest pyramid level at which the footprint spans at most max_taps texels (see
// lenslab/warp/antialias.py for the method). Weights in float64, in the order of the NumPy reference.
#include <algorithm>
#include <vector>

#include "sampler.h"

namespace lenslab {
namespace {

constexpr int WINDOW = 16;  // texels: the window of weights a footprint is gathered through

inline double tent_cdf(double u) {
    double v = std::min(1.0, std::max(-1.0, u));
    return 0.5 + v - 0.5 * v * std::fabs(v);
}

// k[:n] = weights of texels i0..i0+n-1 of the tent averaged over a box of `width` centred at x; their sum.
inline double tent_box_weights(double x, double width, int64_t i0, int64_t n, double* k) {
    double s = 0.0;
    if (width < 1e-6) {
        for (int64_t i = 0; i < n; ++i) {
            k[i] = std::max(0.0, 1.0 - std::fabs(x - double(i0 + i)));
            s += k[i];
        }
        return s;
    }
    double hw = 0.5 * width, inv = 1.0 / width;
    for (int64_t i = 0; i < n; ++i) {
        double d = x - double(i0 + i);
        k[i] = (tent_cdf(d + hw) - tent_cdf(d - hw)) * inv;
        s += k[i];
    }
    return s;
}

inline int64_t ifloor(double v) { return int64_t(dfloor(v)); }

// NC > 0: that many channels, known to the compiler; NC == 0: nc (<= 64) at run time
template <int NC>
void footprint_t(const float* __restrict__ level0, const float* __restrict__ rest, const int64_t* shapes,
                 const int64_t* offsets, int64_t nlev, int64_t nc_, const float* __restrict__ xs,
                 const float* __restrict__ ys, const bool* __restrict__ valid, const float* __restrict__ foot,
                 int64_t npix, int64_t ns, Border b, FootprintParams fp, float* __restrict__ out,
                 float* __restrict__ alpha) {
    const int64_t nc = NC > 0 ? NC : nc_;
    const double inv = 1.0 / double(ns);
    const double h0 = double(shapes[0]);
    double kx[WINDOW], ky[WINDOW], wgt[WINDOW * WINDOW];
    double acc[NC > 0 ? NC : 64];
    for (int64_t q = 0; q < npix; ++q) {
        for (int64_t ch = 0; ch < nc; ++ch) acc[ch] = 0.0;
        int64_t hits = 0;
        for (int64_t s = q * ns; s < (q + 1) * ns; ++s) {
            if (!valid[s]) continue;
            ++hits;
            const float* f = foot + 4 * s;
            double ax = f[0], ay = f[1], bx = f[2], by = f[3];
            double la = std::sqrt(ax * ax + ay * ay), lb = std::sqrt(bx * bx + by * by);
            double longest = std::max(la, lb);
            int64_t lev = 0;
            while (lev + 1 < nlev && longest > fp.max_taps * double(int64_t(1) << lev)) ++lev;
            int64_t lh = shapes[2 * lev], lw = shapes[2 * lev + 1];
            double scale = double(lh) / h0;
            double sxx = (ax * ax + bx * bx) * scale * scale;
            double syy = (ay * ay + by * by) * scale * scale;
            double sxy = (ax * ay + bx * by) * scale * scale;
            double cx = (double(xs[s]) + 0.5) * scale - 0.5;
            double cy = (double(ys[s]) + 0.5) * scale - 0.5;
            int64_t na, nb, nsl;
            double bw, bh;
            if (sxx <= 9.0 && syy <= 9.0 && std::fabs(sxy) <= fp.axis_tol) {
                na = nb = nsl = 1;
                bw = std::sqrt(sxx);
                bh = std::sqrt(syy);
            } else {
                na = std::max<int64_t>(1, -ifloor(-(la * scale * fp.density)));
                nb = std::max<int64_t>(1, -ifloor(-(lb * scale * fp.density)));
                nsl = na * nb;
                double ua = ax / double(na), ub = bx / double(nb), va = ay / double(na), vb = by / double(nb);
                bw = scale * std::sqrt(ua * ua + ub * ub);
                bh = scale * std::sqrt(va * va + vb * vb);
            }
            bw = std::min(3.0, bw);
            bh = std::min(3.0, bh);
            const float* buf = lev == 0 ? level0 : rest;
            const int64_t base = offsets[lev];
            if (nsl == 1) {  // one box: separable weights, read directly
                int64_t i0 = ifloor(cx - 1.0 - 0.5 * bw) + 1, j0 = ifloor(cy - 1.0 - 0.5 * bh) + 1;
                int64_t ni = std::min<int64_t>(ifloor(cx + 1.0 + 0.5 * bw) + 1 - i0, WINDOW);
                int64_t nj = std::min<int64_t>(ifloor(cy + 1.0 + 0.5 * bh) + 1 - j0, WINDOW);
                double norm = 1.0 / (tent_box_weights(cx, bw, i0, ni, kx) * tent_box_weights(cy, bh, j0, nj, ky));
                bool inside = i0 >= 0 && j0 >= 0 && i0 + ni <= lw && j0 + nj <= lh;
                for (int64_t j = 0; j < nj; ++j) {
                    double wj = ky[j] * norm;
                    for (int64_t i = 0; i < ni; ++i) {
                        double ww = kx[i] * wj;
                        int64_t ii = i0 + i, jj = j0 + j;
                        if (!inside) fold_index(ii, jj, lw, lh, b.wrap, b.top, b.bottom);
                        const float* t = buf + base + (jj * lw + ii) * nc;
                        for (int64_t ch = 0; ch < nc; ++ch) acc[ch] += ww * double(t[ch]);
                    }
                }
                continue;
            }
            double ex = 0.5 * scale * (std::fabs(ax) * (1.0 - 1.0 / double(na)) + std::fabs(bx) * (1.0 - 1.0 / double(nb)))
                        + 1.0 + 0.5 * bw;
            double ey = 0.5 * scale * (std::fabs(ay) * (1.0 - 1.0 / double(na)) + std::fabs(by) * (1.0 - 1.0 / double(nb)))
                        + 1.0 + 0.5 * bh;
            int64_t wx0 = ifloor(cx - ex) + 1, wy0 = ifloor(cy - ey) + 1;
            int64_t nwx = std::min<int64_t>(ifloor(cx + ex) - wx0 + 1, WINDOW);
            int64_t nwy = std::min<int64_t>(ifloor(cy + ey) - wy0 + 1, WINDOW);
            for (int64_t j = 0; j < nwy; ++j)
                for (int64_t i = 0; i < nwx; ++i) wgt[j * WINDOW + i] = 0.0;
            double cell = 1.0 / double(nsl);
            double rx = 1.0 + 0.5 * bw, ry = 1.0 + 0.5 * bh;
            for (int64_t c = 0; c < nsl; ++c) {
                double fa = (double(c % na) + 0.5) / double(na) - 0.5;
                double fb = (double(c / na) + 0.5) / double(nb) - 0.5;
                double px = cx + (fa * ax + fb * bx) * scale;
                double py = cy + (fa * ay + fb * by) * scale;
                int64_t i0 = std::max(ifloor(px - rx) + 1, wx0), j0 = std::max(ifloor(py - ry) + 1, wy0);
                int64_t ni = std::min(ifloor(px + rx) + 1, wx0 + nwx) - i0;
                int64_t nj = std::min(ifloor(py + ry) + 1, wy0 + nwy) - j0;
                if (ni <= 0 || nj <= 0) continue;
                double sx = tent_box_weights(px, bw, i0, ni, kx);
                double sy = tent_box_weights(py, bh, j0, nj, ky);
                double norm = cell / (sx * sy);
                for (int64_t j = 0; j < nj; ++j) {
                    double wj = ky[j] * norm;
                    double* row = wgt + (j0 - wy0 + j) * WINDOW + (i0 - wx0);
                    for (int64_t i = 0; i < ni; ++i) row[i] += kx[i] * wj;
                }
            }
            bool inside = wx0 >= 0 && wy0 >= 0 && wx0 + nwx <= lw && wy0 + nwy <= lh;
            for (int64_t j = 0; j < nwy; ++j) {
                for (int64_t i = 0; i < nwx; ++i) {
                    double ww = wgt[j * WINDOW + i];
                    if (ww == 0.0) continue;
                    int64_t ii = wx0 + i, jj = wy0 + j;
                    if (!inside) fold_index(ii, jj, lw, lh, b.wrap, b.top, b.bottom);
                    const float* t = buf + base + (jj * lw + ii) * nc;
                    for (int64_t ch = 0; ch < nc; ++ch) acc[ch] += ww * double(t[ch]);
                }
            }
        }
        for (int64_t ch = 0; ch < nc; ++ch) out[q * nc + ch] = float(acc[ch] * inv);
        alpha[q] = float(double(hits) * inv);
    }
}

}  // namespace

void footprint(const float* level0, const float* rest, const int64_t* shapes, const int64_t* offsets, int64_t nlev,
               int64_t nc, const float* xs, const float* ys, const bool* valid, const float* foot, int64_t npix,
               int64_t ns, Border b, FootprintParams fp, float* out, float* alpha) {
    switch (nc) {
        case 1: return footprint_t<1>(level0, rest, shapes, offsets, nlev, nc, xs, ys, valid, foot, npix, ns, b, fp, out, alpha);
        case 3: return footprint_t<3>(level0, rest, shapes, offsets, nlev, nc, xs, ys, valid, foot, npix, ns, b, fp, out, alpha);
        case 4: return footprint_t<4>(level0, rest, shapes, offsets, nlev, nc, xs, ys, valid, foot, npix, ns, b, fp, out, alpha);
        default: return footprint_t<0>(level0, rest, shapes, offsets, nlev, nc, xs, ys, valid, foot, npix, ns, b, fp, out, alpha);
    }
}

void edges(const float* src, int64_t sw, int64_t sh, int64_t nc, const int64_t* idx, const float* exs,
           const float* eys, const bool* evalid, int64_t m, int64_t kk, int64_t ns, int64_t width, Border b,
           float* out, float* alpha) {
    (void)width;
    std::vector<double> acc(nc);
    for (int64_t e = 0; e < m; ++e) {
        int64_t pix = idx[e] / ns;
        std::fill(acc.begin(), acc.end(), 0.0);
        int64_t hits = 0;
        for (int64_t q = 0; q < kk; ++q) {
            if (!evalid[e * kk + q]) continue;
            ++hits;
            double x = exs[e * kk + q], y = eys[e * kk + q];
            double fx0 = dfloor(x), fy0 = dfloor(y);
            int64_t i0 = int64_t(fx0), j0 = int64_t(fy0);
            double tx = x - fx0, ty = y - fy0;
            for (int dj = 0; dj < 2; ++dj) {
                double wy = dj ? ty : 1.0 - ty;
                if (wy == 0.0) continue;
                for (int di = 0; di < 2; ++di) {
                    double wx = di ? tx : 1.0 - tx;
                    if (wx == 0.0) continue;
                    int64_t ii = i0 + di, jj = j0 + dj;
                    fold_index(ii, jj, sw, sh, b.wrap, b.top, b.bottom);
                    double ww = wx * wy;
                    const float* t = src + (jj * sw + ii) * nc;
                    for (int64_t ch = 0; ch < nc; ++ch) acc[ch] += ww * double(t[ch]);
                }
            }
        }
        double scale = 1.0 / double(kk * ns);
        for (int64_t ch = 0; ch < nc; ++ch) out[pix * nc + ch] = float(double(out[pix * nc + ch]) + acc[ch] * scale);
        alpha[pix] = float(double(alpha[pix]) + double(hits) * scale);
    }
}

}  // namespace lenslab
