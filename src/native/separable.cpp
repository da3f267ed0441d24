// The separable samplers (lenslab.warp.filters): nearest, tent, Catmull-Rom and Lanczos-3 weights in float64
// from the exact position, every tap folded across the seam, the poles or into the neighbouring piece (a cube
// face across its edge). Built without fused multiply-adds: the bits of the NumPy reference
// (lenslab/warp/kernels/filter_reference.py). Each axis's weights are computed once per sample (Lanczos-3 from one
// sine and cosine, no division per tap); taps inside the image are read in place, row by row, and prefetched.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <vector>

#include "kernels.h"
#include "lattice.h"

namespace lenslab {

namespace {

constexpr double PI = 3.141592653589793;
constexpr double HALF_SQRT3 = 0.8660254037844386;  // sin(pi / 3)
// cos and sin of k pi / 3, k = -3..3: the rotations that turn sin(pi g / 3) into sin(pi (g + k) / 3)
constexpr double ROT_COS[7] = {-1.0, -0.5, 0.5, 1.0, 0.5, -0.5, -1.0};
constexpr double ROT_SIN[7] = {0.0, -HALF_SQRT3, -HALF_SQRT3, 0.0, HALF_SQRT3, HALF_SQRT3, 0.0};

inline double weight(int kind, double t) {  // tent and Catmull-Rom at offset t
    const double a = std::fabs(t);
    if (kind == 1) return 1.0 - a > 0.0 ? 1.0 - a : 0.0;
    if (a < 1.0) return (1.5 * a - 2.5) * a * a + 1.0;
    if (a < 2.0) return ((-0.5 * a + 2.5) * a - 4.0) * a + 2.0;
    return 0.0;
}

// sin z and cos z for |z| <= pi / 6, Taylor series to z^15 and z^16 (the next terms are below 1e-19 relative):
// within an ulp or two of the C library's, with no call. SIN_C[i] = (-1)^i / (2 i + 1)!, COS_C[i] = (-1)^i / (2 i)!.
constexpr double SIN_C[8] = {1.0, -1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0, 1.0 / 362880.0, -1.0 / 39916800.0,
                             1.0 / 6227020800.0, -1.0 / 1307674368000.0};
constexpr double COS_C[9] = {1.0, -0.5, 1.0 / 24.0, -1.0 / 720.0, 1.0 / 40320.0, -1.0 / 3628800.0,
                             1.0 / 479001600.0, -1.0 / 87178291200.0, 1.0 / 20922789888000.0};

inline void small_sincos(double z, double& s, double& c) {
    const double z2 = z * z;
    double ps = SIN_C[7], pc = COS_C[8];
    for (int i = 6; i >= 0; --i) ps = ps * z2 + SIN_C[i];
    for (int i = 7; i >= 0; --i) pc = pc * z2 + COS_C[i];
    s = z * ps;
    c = pc;
}

}  // namespace

// The Lanczos-3 weights of taps i0 - 2 .. i0 + 3 (i0 = floor(x)), unnormalised, from one sine and cosine: with
// g = x - round(x) (|g| <= 1/2, exact) and the tap at offset d = g + k, sin(pi d) = (-1)^k sin(pi g) = (-1)^k
// s (3 - 4 s^2) for s = sin(pi g / 3) (no cancellation: |s| <= 1/2), and sin(pi d / 3) = s cos(k pi / 3) +
// c sin(k pi / 3). The window 3 sin(pi d) sin(pi d / 3) / (pi d)^2 is returned times 3 prod_s (pi d_s)^2 / 3
// (a factor the normalisation takes out): sin(pi d) sin(pi d / 3) prod_{s != t} (pi d_s)^2, no division. At
// |g| < 1e-60 (never for a float32 position but 0) the weights are the tap's own, to within 1e-60.
void lanczos_weights(double x, double* w) {
    const double i0 = std::floor(x), n = std::floor(x + 0.5);
    const double g = x - n;
    if (std::fabs(g) < 1e-60) {
        for (int t = 0; t < 6; ++t) w[t] = 0.0;
        w[int(n - i0) + 2] = 1.0;
        return;
    }
    double s, c;
    small_sincos(PI * g / 3.0, s, c);
    const double sp = s * (3.0 - 4.0 * s * s);
    const int r0 = int(n - i0) + 5;  // k + 3 of tap 0 (tap t: k = n - i0 + 2 - t, -3..3)
    double den[6], pre[6], suf[6];
    for (int t = 0; t < 6; ++t) {
        const double pd = PI * (x - (i0 - 2.0 + double(t)));
        den[t] = pd * pd;
    }
    pre[0] = 1.0;
    suf[5] = 1.0;
    for (int t = 1; t < 6; ++t) pre[t] = pre[t - 1] * den[t - 1];
    for (int t = 4; t >= 0; --t) suf[t] = suf[t + 1] * den[t + 1];
    for (int t = 0; t < 6; ++t) {
        const int r = r0 - t;
        const double sd = (r & 1) ? sp : -sp;  // (-1)^k sin(pi g)
        w[t] = sd * (s * ROT_COS[r] + c * ROT_SIN[r]) * (pre[t] * suf[t]);
    }
}

namespace {

// The 2 K weights of one axis at position x (K 1 tent, 2 Catmull-Rom, 3 Lanczos-3), each times the reciprocal
// of their sum (float64: the sum in tap order, then w * (1 / sum)).
template <int K>
inline void weights_of(double x, double* w) {
    const double i0 = std::floor(x);
    if (K == 3) lanczos_weights(x, w);
    else
        for (int t = 0; t < 2 * K; ++t) w[t] = weight(K, x - (i0 - double(K - 1 - t)));
    double sum = 0.0;
    for (int t = 0; t < 2 * K; ++t) sum += w[t];
    const double inv = 1.0 / sum;
    for (int t = 0; t < 2 * K; ++t) w[t] *= inv;
}

}  // namespace

void axis_weights(int kind, double x, double* w) {
    if (kind == 3) weights_of<3>(x, w);
    else if (kind == 2) weights_of<2>(x, w);
    else weights_of<1>(x, w);
}

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

namespace {

inline int64_t piece_at(double x, double y, const Pieces& pc) {
    const double fc = std::floor((x + 0.5) / double(pc.cw)), fr = std::floor((y + 0.5) / double(pc.ch));
    if (!(fc >= 0.0 && fr >= 0.0 && fc < double(pc.gc) && fr < double(pc.gr))) return -1;
    return pc.grid[int64_t(fr) * pc.gc + int64_t(fc)];
}

// samples ahead whose tap rows are asked of the memory (as the bilinear samplers do, sampler.cpp)
constexpr int64_t PREFETCH = 16;

// One sample's value added to acc, all taps inside the image (rows read in place, no folding): each row's taps
// weighted by wx, the rows by wy (normalised weights), in the reference's order; a tap of weight 0 is not read.
template <int R, int NC>
inline void add_inside(const float* src, int64_t sw, int64_t nc, int64_t i0, int64_t j0, const double* wx,
                       const double* wy, double* acc) {
    const int64_t cn = NC > 0 ? NC : nc;
    double v[NC > 0 ? NC : 4], rs[NC > 0 ? NC : 4];
    bool zx = false;
    for (int t = 0; t < 2 * R; ++t) zx |= wx[t] == 0.0;
    const float* row = src + ((j0 - R + 1) * sw + (i0 - R + 1)) * cn;
    for (int64_t c0 = 0; c0 < cn; c0 += (NC > 0 ? NC : 4)) {  // channels four at a time (NC: all at once)
        const int64_t m = NC > 0 ? NC : std::min<int64_t>(4, cn - c0);
        for (int64_t c = 0; c < m; ++c) v[c] = 0.0;
        const float* rw = row + c0;
        for (int tj = 0; tj < 2 * R; ++tj, rw += sw * cn) {
            if (wy[tj] == 0.0) continue;
            for (int64_t c = 0; c < m; ++c) rs[c] = 0.0;
            for (int ti = 0; ti < 2 * R; ++ti) {
                if (zx && wx[ti] == 0.0) continue;
                const float* px = rw + ti * cn;
                for (int64_t c = 0; c < m; ++c) rs[c] += wx[ti] * double(px[c]);
            }
            for (int64_t c = 0; c < m; ++c) v[c] += wy[tj] * rs[c];
        }
        for (int64_t c = 0; c < m; ++c) acc[c0 + c] += v[c];
    }
}

typedef double v4d __attribute__((vector_size(32)));
typedef float v4f __attribute__((vector_size(16)));

// add_inside for RGB: each tap's three channels (and the next float, weighted but dropped) in one vector, lane by
// lane the same products and sums as the scalar loop. The fourth float of the last tap is inside the source: the
// caller keeps the window off the image's last pixel.
template <int R>
inline void add_inside_rgb(const float* src, int64_t sw, int64_t i0, int64_t j0, const double* wx, const double* wy,
                           double* acc) {
    bool zx = false;
    for (int t = 0; t < 2 * R; ++t) zx |= wx[t] == 0.0;
    const float* row = src + ((j0 - R + 1) * sw + (i0 - R + 1)) * 3;
    v4d v = {0.0, 0.0, 0.0, 0.0};
    for (int tj = 0; tj < 2 * R; ++tj, row += sw * 3) {
        if (wy[tj] == 0.0) continue;
        v4d rs = {0.0, 0.0, 0.0, 0.0};
        for (int ti = 0; ti < 2 * R; ++ti) {
            if (zx && wx[ti] == 0.0) continue;
            v4f p;
            std::memcpy(&p, row + ti * 3, sizeof p);
            rs += wx[ti] * __builtin_convertvector(p, v4d);
        }
        v += wy[tj] * rs;
    }
    for (int c = 0; c < 3; ++c) acc[c] += v[c];
}

}  // namespace

void separable(const float* src, int64_t sw, int64_t sh, int64_t nc, const float* xs, const float* ys,
               const bool* valid, int64_t npix, int64_t ns, bool wrap, bool top, bool bottom, const Pieces& pc,
               int kind, float* out, float* alpha) {
    const double inv = 1.0 / double(ns);
    const int rad = std::max(kind, 1);
    std::vector<double> acc(static_cast<size_t>(nc)), val(acc), rsum(acc);
    double wx[6], wy[6];  // one axis's weights, computed once per sample
    auto fold = [&](int64_t& i, int64_t& j, int64_t piece) {
        if (piece >= 0) fold_piece(i, j, piece, pc.table);
        else fold_index(i, j, sw, sh, wrap, top, bottom);
    };
    for (int64_t q = 0; q < npix; ++q) {
        std::fill(acc.begin(), acc.end(), 0.0);
        int64_t hits = 0;
        for (int64_t k = q * ns; k < (q + 1) * ns; ++k) {
            if (k + PREFETCH < npix * ns) {  // a sample a few ahead: its tap rows
                const int64_t i = int64_t(int32_t(xs[k + PREFETCH])) - rad + 1;
                const int64_t j = int64_t(int32_t(ys[k + PREFETCH])) - rad + 1;
                if (i >= 0 && j >= 0 && i + 2 * rad <= sw && j + 2 * rad <= sh) {
                    const float* t = src + (j * sw + i) * nc;
                    for (int r = 0; r < 2 * rad; ++r, t += sw * nc) __builtin_prefetch(t);
                }
            }
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
            if (kind == 3) { weights_of<3>(x, wx); weights_of<3>(y, wy); }
            else if (kind == 2) { weights_of<2>(x, wx); weights_of<2>(y, wy); }
            else { weights_of<1>(x, wx); weights_of<1>(y, wy); }
            if (piece < 0 && i0 - rad + 1 >= 0 && j0 - rad + 1 >= 0 && i0 + rad < sw && j0 + rad < sh) {
                double* a = acc.data();
                const bool last = j0 + rad == sh - 1 && i0 + rad == sw - 1;  // the window ends on the last pixel
                if (kind == 3) {
                    if (nc == 3 && !last) add_inside_rgb<3>(src, sw, i0, j0, wx, wy, a);
                    else if (nc == 3) add_inside<3, 3>(src, sw, nc, i0, j0, wx, wy, a);
                    else add_inside<3, 0>(src, sw, nc, i0, j0, wx, wy, a);
                } else if (kind == 2) {
                    if (nc == 3 && !last) add_inside_rgb<2>(src, sw, i0, j0, wx, wy, a);
                    else if (nc == 3) add_inside<2, 3>(src, sw, nc, i0, j0, wx, wy, a);
                    else add_inside<2, 0>(src, sw, nc, i0, j0, wx, wy, a);
                } else {
                    if (nc == 3 && !last) add_inside_rgb<1>(src, sw, i0, j0, wx, wy, a);
                    else if (nc == 3) add_inside<1, 3>(src, sw, nc, i0, j0, wx, wy, a);
                    else add_inside<1, 0>(src, sw, nc, i0, j0, wx, wy, a);
                }
                continue;
            }
            std::fill(val.begin(), val.end(), 0.0);
            for (int tj = 0; tj < 2 * rad; ++tj) {  // the same sums, each tap folded
                if (wy[tj] == 0.0) continue;
                std::fill(rsum.begin(), rsum.end(), 0.0);
                for (int ti = 0; ti < 2 * rad; ++ti) {
                    if (wx[ti] == 0.0) continue;
                    int64_t ii = i0 - rad + 1 + ti, jj = j0 - rad + 1 + tj;
                    fold(ii, jj, piece);
                    const float* px = src + (jj * sw + ii) * nc;
                    for (int64_t c = 0; c < nc; ++c) rsum[size_t(c)] += wx[ti] * double(px[c]);
                }
                for (int64_t c = 0; c < nc; ++c) val[size_t(c)] += wy[tj] * rsum[size_t(c)];
            }
            for (int64_t c = 0; c < nc; ++c) acc[size_t(c)] += val[size_t(c)];
        }
        for (int64_t c = 0; c < nc; ++c) {  // negative lobes overshoot: a finite source stays finite
            const double v = acc[size_t(c)] * inv;
            out[q * nc + c] = float(v > FLT_MAX ? double(FLT_MAX) : (v < -FLT_MAX ? -double(FLT_MAX) : v));
        }
        alpha[q] = float(double(hits) * inv);
    }
}

}  // namespace lenslab
