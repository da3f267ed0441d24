// The lens models' array kernels (see lens_kernels.h): the same steps as the models' former numba kernels,
// compiled ahead of time, so a lens costs nothing to start on a new machine.
#include "lens_kernels.h"
#include "lens_pixel_steps.h"

#include <algorithm>
#include <cmath>

#ifdef LENSLAB_MVEC  // glibc's vector maths (libmvec, glibc 2.35 or later; CMakeLists.txt finds it)
#include <immintrin.h>
extern "C" __m256d _ZGVdN4vv_atan2(__m256d, __m256d);
extern "C" __m256d _ZGVdN4vv_hypot(__m256d, __m256d);
#endif

namespace lenslab::lens {

namespace {

inline bool finite(double v) { return std::isfinite(v); }

// the slack rule of an image test: within `slack` px of the edges counts, moved onto them
inline bool store(int64_t i, double u, double v, const Frame& f, double* xy, bool* ok) {
    if (u >= -f.slack && u <= f.width + f.slack && v >= -f.slack && v <= f.height + f.slack) {
        xy[2 * i] = std::min(std::max(u, 0.0), f.width);
        xy[2 * i + 1] = std::min(std::max(v, 0.0), f.height);
        ok[i] = true;
        return true;
    }
    return false;
}

// lenslab direction i (any length) as a unit ray in OpenCV's frame (y down); false unless finite and non-zero
inline bool cv_ray(const double* d, int64_t i, double& X, double& Y, double& Z) {
    X = d[3 * i];
    Y = -d[3 * i + 1];
    Z = d[3 * i + 2];
    const double n2 = X * X + Y * Y + Z * Z;
    if (!(n2 > 0.0 && n2 < INF)) return false;
    const double inv = 1.0 / std::sqrt(n2);
    X *= inv;
    Y *= inv;
    Z *= inv;
    return true;
}

struct Distorted { double x, y, j11, j12, j21, j22; };

// OpenCV's distortion of one point and its Jacobian
inline Distorted distort(double x, double y, const Distortion& m) {
    const double r2 = x * x + y * y;
    const VD R = rational_radial(std::sqrt(r2), m.a, m.b);
    const double* s = m.s;
    Distorted o;
    o.x = x * R.v + 2.0 * m.p1 * x * y + m.p2 * (r2 + 2.0 * x * x) + s[0] * r2 + s[1] * r2 * r2;
    o.y = y * R.v + m.p1 * (r2 + 2.0 * y * y) + 2.0 * m.p2 * x * y + s[2] * r2 + s[3] * r2 * r2;
    const double dsx = s[0] + 2.0 * s[1] * r2;
    const double dsy = s[2] + 2.0 * s[3] * r2;
    o.j11 = R.v + 2.0 * x * x * R.d + 2.0 * m.p1 * y + 6.0 * m.p2 * x + 2.0 * x * dsx;
    o.j12 = 2.0 * x * y * R.d + 2.0 * m.p1 * x + 2.0 * m.p2 * y + 2.0 * y * dsx;
    o.j21 = 2.0 * x * y * R.d + 2.0 * m.p1 * x + 2.0 * m.p2 * y + 2.0 * x * dsy;
    o.j22 = R.v + 2.0 * y * y * R.d + 6.0 * m.p1 * y + 2.0 * m.p2 * x + 2.0 * y * dsy;
    return o;
}

struct Undistorted { bool ok; double x, y; int64_t its; };

// Undistort one point of the normalised plane: the radial solve, then (tangential terms) a 2-D Newton whose
// steps are halved to stay inside the fold
inline Undistorted undistort(double xd, double yd, const Distortion& m, double hi, double f_hi, bool strict,
                             const Table& table, const Solver& s, double tol_2d, int64_t max_iter_2d) {
    const double fold2 = m.fold * m.fold;
    const double rd = std::sqrt(xd * xd + yd * yd);
    const double h2 = hi * hi;  // tangential and prism terms move a point by at most this inside the bracket
    const double* ps = m.s;
    const double lim = f_hi + (m.tangential ? ((3.0 * (std::fabs(m.p1) + std::fabs(m.p2)) + std::fabs(ps[0])
                                                + std::fabs(ps[2])) * h2 + (std::fabs(ps[1]) + std::fabs(ps[3])) * h2 * h2)
                                            : 0.0);
    if (!(strict ? rd < lim : rd <= lim)) return {false, 0.0, 0.0, 0};  // also false for NaN
    const double rr = rd < f_hi ? rd : f_hi * (1.0 - 1e-9);
    const double b3[3] = {m.b[0], m.b[1], m.b[2]};
    const Coeffs c{m.a, 4, b3, 3};
    const Root r = solve_one(RATIONAL, c, rr, hi, table_guess(rr, table.v, table.len, table.step, false), s);
    if (!r.ok || (strict && !(r.x < m.fold))) return {false, 0.0, 0.0, r.its};
    double x = rd > 0.0 ? xd * (r.x / rd) : xd;
    double y = rd > 0.0 ? yd * (r.x / rd) : yd;
    if (!m.tangential) return {true, x, y, r.its};
    bool ok = false;
    int64_t it2 = 0;
    for (int64_t it = 1; it <= max_iter_2d; ++it) {
        it2 = it;
        const Distorted f = distort(x, y, m);
        const double ex = f.x - xd, ey = f.y - yd;
        if (std::sqrt(ex * ex + ey * ey) <= tol_2d * std::max(1.0, rd)) {
            ok = true;
            break;
        }
        const double det = f.j11 * f.j22 - f.j12 * f.j21;
        const double sx = (f.j22 * ex - f.j12 * ey) / det;
        const double sy = (f.j11 * ey - f.j21 * ex) / det;
        double step = 1.0;
        for (int h = 0; h < 30; ++h) {  // halve the step until it stays inside the fold
            const double nx = x - step * sx, ny = y - step * sy;
            if (nx * nx + ny * ny < fold2) break;
            step *= 0.5;
        }
        x -= step * sx;
        y -= step * sy;
    }
    if (ok) {
        const Distorted f = distort(x, y, m);
        ok = f.j11 * f.j22 - f.j12 * f.j21 > 0.0 && x * x + y * y < fold2;
    }
    return {ok, x, y, r.its + it2};
}

}  // namespace

void perspective_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    const double w = p[0], h = p[1], t = p[2], tv = p[3], aspect = p[4], slack = p[5];
    for (int64_t i = 0; i < n; ++i) {
        clear2(i, xy, ok);
        double u, v;
        if (pinhole_uv(d, i, t, tv, u, v)) uv_pixel(i, u, v, w, h, aspect, slack, xy, ok);
    }
}

void hammer_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    const double w = p[0], h = p[1], aspect = p[2], slack = p[3];
    for (int64_t i = 0; i < n; ++i) {
        clear2(i, xy, ok);
        double dx, dy, dz;
        if (!unit_dir(d, i, dx, dy, dz)) continue;
        const double c = std::hypot(dx, dz);
        const double a = std::fabs(dz) + c;
        double hh = 0.0;
        if (a > 0.0) {
            hh = c / a;
            hh *= 0.5;
            hh = std::sqrt(hh);
        }
        const double big = a * hh, small = std::fabs(dx) * hh;
        const bool front = dz >= 0.0;
        const double cc = front ? big : small;
        const double cs = std::copysign(front ? small : big, dx);
        const double z = std::sqrt(cc + 1.0);
        uv_pixel(i, cs / z, dy / (z * 2.0), w, h, aspect, slack, xy, ok);
    }
}

// The longitude atan2(dx, dz), cos(latitude) hypot(dx, dz) and latitude atan2(dy, hypot) of `m` <= 4 unit directions
// (x, y, z in a[0..3], a[4..7], a[8..11]; written over them). With glibc's vector maths (libmvec) four at a time; every
// element takes the same path whatever its place in a call (a short block is padded), so a map's values do not
// depend on how the warp cut it into bands.
inline void lon_lat4(double* a) {
#ifdef LENSLAB_MVEC
    const __m256d x = _mm256_loadu_pd(a), y = _mm256_loadu_pd(a + 4), z = _mm256_loadu_pd(a + 8);
    const __m256d c = _ZGVdN4vv_hypot(x, z);
    _mm256_storeu_pd(a, _ZGVdN4vv_atan2(x, z));
    _mm256_storeu_pd(a + 4, _ZGVdN4vv_atan2(y, c));
#else
    for (int j = 0; j < 4; ++j) {
        const double x = a[j], y = a[4 + j], z = a[8 + j];
        a[j] = std::atan2(x, z);
        a[4 + j] = std::atan2(y, std::hypot(x, z));
    }
#endif
}

void equirect_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    const double w = p[0], h = p[1], lon0 = p[2], lon1 = p[3], lat0 = p[4], lat1 = p[5], e = p[8];
    const bool full = p[6] != 0.0, wraps = p[7] != 0.0;
    for (int64_t i0 = 0; i0 < n; i0 += 4) {
        const int64_t m = std::min<int64_t>(4, n - i0);
        double a[12] = {0.0};
        bool good[4] = {false, false, false, false};
        for (int64_t j = 0; j < m; ++j) {
            const int64_t i = i0 + j;
            clear2(i, xy, ok);
            double dx = d[3 * i], dy = d[3 * i + 1], dz = d[3 * i + 2];
            const double n2 = dx * dx + dy * dy + dz * dz;
            if (!(n2 > 0.0 && finite(n2))) continue;
            const double sn = std::sqrt(n2);
            a[j] = dx / sn;
            a[4 + j] = dy / sn;
            a[8 + j] = dz / sn;
            good[j] = true;
        }
        if (!(good[0] || good[1] || good[2] || good[3])) continue;  // nothing seen: no trigonometry
        lon_lat4(a);
        for (int64_t j = 0; j < m; ++j) {
            if (!good[j]) continue;
            const int64_t i = i0 + j;
            double phi = a[j];
            const double theta = a[4 + j];
            double x, y;
            if (full) {
                x = phi / PI;
                x += 1.0;
                x *= 0.5 * w;
                y = theta / (PI / 2);
                y = 1.0 - y;
                y *= 0.5 * h;
            } else {
                if (!wraps && phi < lon0) phi += 2 * PI;
                x = (phi - lon0) / (lon1 - lon0) * w;
                y = (lat1 - theta) / (lat1 - lat0) * h;
                if (!(x >= -e && x <= w + e && y >= -e && y <= h + e)) continue;
                x = std::min(std::max(x, 0.0), w);
                y = std::min(std::max(y, 0.0), h);
            }
            if (finite(x) && finite(y)) {
                xy[2 * i] = x;
                xy[2 * i + 1] = y;
                ok[i] = true;
            }
        }
    }
}

PixelFn pixel_fn(int64_t id) {
    switch (id) {
        case 0: return equirect_pixels;
        case 1: return perspective_pixels;
        case 2: return hammer_pixels;
        default: return nullptr;
    }
}

void tiled_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    constexpr int64_t B = 256;  // directions per block: the block's buffers stay in the L1 cache
    const int64_t ntiles = int64_t(p[0]);
    double u[3 * B], buf[3 * B], lxy[2 * B];
    bool free_[B], lok[B];
    int64_t idx[B];
    for (int64_t b0 = 0; b0 < n; b0 += B) {
        const int64_t m = std::min(B, n - b0);
        for (int64_t j = 0; j < m; ++j) {
            clear2(b0 + j, xy, ok);
            free_[j] = unit_dir(d + 3 * b0, j, u[3 * j], u[3 * j + 1], u[3 * j + 2]);
        }
        const double* t = p + 1;
        for (int64_t k = 0; k < ntiles; ++k) {
            const PixelFn fn = pixel_fn(int64_t(t[0]));
            const int64_t np_ = int64_t(t[1]);
            const double reach = t[2];
            const double* axis = t + 3;
            const double* R = t + 6;
            const double ox = t[15], oy = t[16], limx = t[17], limy = t[18];
            int64_t c = 0;
            for (int64_t j = 0; j < m; ++j) {
                if (!free_[j]) continue;
                const double* v = u + 3 * j;
                if (reach > -1.0 && !(axis[0] * v[0] + axis[1] * v[1] + axis[2] * v[2] >= reach)) continue;
                for (int q = 0; q < 3; ++q) buf[3 * c + q] = v[0] * R[q] + v[1] * R[3 + q] + v[2] * R[6 + q];
                idx[c++] = j;
            }
            if (c && fn) {
                fn(buf, c, t + 19, lxy, lok);
                for (int64_t e = 0; e < c; ++e) {
                    if (!lok[e]) continue;
                    const int64_t i = b0 + idx[e];
                    xy[2 * i] = std::min(lxy[2 * e], limx) + ox;  // off the tile's right and bottom edges
                    xy[2 * i + 1] = std::min(lxy[2 * e + 1], limy) + oy;
                    ok[i] = true;
                    free_[idx[e]] = false;
                }
            }
            t += 19 + np_;
        }
    }
}

void division_unbend(const double* uv, int64_t n, double k1, double k2, double hi, double f_hi, bool strict, bool pole,
                     const Table& table, const Solver& s, double* out, bool* ok) {
    const double ab[2] = {k1, k2};
    const Coeffs c{ab, 2, ab, 2};
    for (int64_t i = 0; i < n; ++i) {
        clear2(i, out, ok);
        const double u = uv[2 * i], v = uv[2 * i + 1];
        const double t = std::sqrt(u * u + v * v);
        if (!(strict ? t < f_hi : t <= f_hi)) continue;
        const double x0 = table_guess(t, table.v, table.len, table.step, false);
        const Root r = (pole && t > 1.0) ? solve_one(DIVISION_RECIPROCAL, c, -1.0 / t, hi, x0, s)
                                         : solve_one(DIVISION, c, t, hi, x0, s);
        if (!r.ok) continue;
        const double sq = r.x * r.x;
        const double den = 1.0 + sq * (k1 + k2 * sq);  // r_d / r_u, with the limit 1 at the centre
        out[2 * i] = u * den;
        out[2 * i + 1] = v * den;
        ok[i] = true;
    }
}

void brown_bend(const double* uv, int64_t n, double k1, double k2, double hi, double rd_fold, const Table& table,
                const Solver& s, double* out, bool* ok) {
    const double ab[2] = {k1, k2};
    const Coeffs c{ab, 2, ab, 2};
    for (int64_t i = 0; i < n; ++i) {
        clear2(i, out, ok);
        const double u = uv[2 * i], v = uv[2 * i + 1];
        const double t = std::sqrt(u * u + v * v);
        if (!(t < rd_fold)) continue;
        const Root r = solve_one(BROWN, c, t, hi, table_guess(t, table.v, table.len, table.step, false), s);
        if (!r.ok) continue;
        const double scale = t > 0.0 ? r.x / t : 1.0;
        out[2 * i] = u * scale;
        out[2 * i + 1] = v * scale;
        ok[i] = true;
    }
}

void tan_fisheye_dir_to_uv(const double* d, int64_t n, double F, double hi, double psi_max, bool strict,
                           const Table& table, const Solver& s, double* out, bool* ok) {
    const double ab[2] = {F, 0.0};
    const Coeffs c{ab, 2, ab, 2};
    for (int64_t i = 0; i < n; ++i) {
        clear2(i, out, ok);
        const double dx = d[3 * i], dy = d[3 * i + 1];
        const double rho = std::sqrt(dx * dx + dy * dy);
        const double theta = std::atan2(rho, d[3 * i + 2]);
        if (!(strict ? theta < psi_max : theta <= psi_max)) continue;
        const Root r = solve_one(TAN_FISHEYE, c, theta, hi, table_guess(theta, table.v, table.len, table.step, true), s);
        if (!r.ok) continue;
        ok[i] = true;  // the axis (rho = 0) is seen, at the centre
        if (rho > 0.0) {
            const double k = r.x / rho;
            out[2 * i] = dx * k;
            out[2 * i + 1] = dy * k;
        }
    }
}

void distort_points(const double* x, const double* y, int64_t n, const Distortion& m, double* xd, double* yd,
                    bool* ok) {
    const double fold2 = m.fold * m.fold;
    for (int64_t i = 0; i < n; ++i) {
        const double xi = x[i], yi = y[i];
        bool seen = xi * xi + yi * yi < fold2;
        Distorted f{0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        if (seen) {
            f = distort(xi, yi, m);
            if (m.tangential) seen = f.j11 * f.j22 - f.j12 * f.j21 > 0.0;
        }
        xd[i] = seen ? f.x : 0.0;
        yd[i] = seen ? f.y : 0.0;
        ok[i] = seen;
    }
}

void calibrated_project(const double* d, int64_t n, int64_t kind, const double* q, const Distortion* dist,
                        const Intrinsics& k, const Frame& frame, double* xy, bool* ok) {
    const double fold2 = dist ? dist->fold * dist->fold : INF;
    for (int64_t i = 0; i < n; ++i) {
        clear2(i, xy, ok);
        double X, Y, Z;
        if (!cv_ray(d, i, X, Y, Z)) continue;
        const P2 m = project_one(kind, X, Y, Z, q);
        if (!m.ok) continue;
        double mx = m.x, my = m.y;
        if (dist) {
            if (!(mx * mx + my * my < fold2)) continue;
            const Distorted f = distort(mx, my, *dist);
            if (dist->tangential && !(f.j11 * f.j22 - f.j12 * f.j21 > 0.0)) continue;
            mx = f.x;
            my = f.y;
        }
        store(i, k.fx * mx + k.skew * my + k.cx + 0.5, k.fy * my + k.cy + 0.5, frame, xy, ok);
    }
}

int64_t calibrated_unproject(const double* xy, int64_t n, int64_t kind, const double* q, const Distortion* dist,
                             double hi, double f_hi, bool strict, const Table& table, const Solver& s, double tol_2d,
                             int64_t max_iter_2d, const Intrinsics& k, double* d, bool* ok) {
    int64_t worst = 0;
    for (int64_t i = 0; i < n; ++i) {
        d[3 * i] = d[3 * i + 1] = d[3 * i + 2] = 0.0;
        ok[i] = false;
        double my = (xy[2 * i + 1] - 0.5 - k.cy) / k.fy;
        double mx = (xy[2 * i] - 0.5 - k.cx - k.skew * my) / k.fx;
        if (!(finite(mx) && finite(my))) continue;
        if (dist) {
            const Undistorted u = undistort(mx, my, *dist, hi, f_hi, strict, table, s, tol_2d, max_iter_2d);
            if (!u.ok) continue;
            mx = u.x;
            my = u.y;
            worst = std::max(worst, u.its);
        }
        const P3 r = unproject_one(kind, mx, my, q);
        if (!r.ok) continue;
        d[3 * i] = r.x;
        d[3 * i + 1] = -r.y;  // OpenCV's y down -> lenslab's y up
        d[3 * i + 2] = r.z;
        ok[i] = true;
    }
    return worst;
}

int64_t ocam_project(const double* d, int64_t n, const double* pol_unit, int64_t npol, double hi, double a_hi,
                     bool strict, const Table& table, const Solver& s, double c, double dd, double e, double xc,
                     double yc, const Frame& frame, double* xy, bool* ok) {
    int64_t worst = 0;
    for (int64_t i = 0; i < n; ++i) {
        clear2(i, xy, ok);
        double X, Y, Z;
        if (!cv_ray(d, i, X, Y, Z)) continue;
        const double lat = std::sqrt(X * X + Y * Y);
        const double t = std::atan2(lat, Z);
        if (!(strict ? t < a_hi : t <= a_hi)) continue;
        const double cs[2] = {std::cos(t), std::sin(t)};
        // solved for u = rho / hi in [0, 1] with pol_unit(u) = pol(u hi) / hi: dimensionless
        const Coeffs co{pol_unit, npol, cs, 2};
        const Root r = solve_one(OCAM, co, 0.0, 1.0, table_guess(t, table.v, table.len, table.step, false) / hi, s);
        if (!r.ok) continue;
        const double rho = r.x * hi;
        worst = std::max(worst, r.its);
        const double kk = lat > 0.0 ? rho / lat : 0.0;
        const double xp = Y * kk, yp = X * kk;
        store(i, e * xp + yp + yc + 0.5, c * xp + dd * yp + xc + 0.5, frame, xy, ok);  // col, row
    }
    return worst;
}

void lensfun_dir_to_pixel(const double* d, int64_t n, int64_t kind, double f, const double* coeffs, int64_t ncoeffs,
                          double r_lim, double cx, double cy, double norm, double* xy, bool* ok) {
    for (int64_t i = 0; i < n; ++i) {
        clear2(i, xy, ok);
        double dx = d[3 * i], dy = d[3 * i + 1], dz = d[3 * i + 2];
        const double nn = std::sqrt(dx * dx + dy * dy + dz * dz);
        if (!(nn > 0.0 && nn < INF)) continue;
        dx /= nn;
        dy /= nn;
        dz /= nn;
        double x, y;
        if (kind == RECTILINEAR) {
            if (!(dz > 0.0)) continue;
            x = f * dx / dz;
            y = f * dy / dz;
        } else {
            const P2 p = (kind == EQUIRECTANGULAR || kind == CYLINDRICAL || kind == EQUAL_AREA_CYLINDRICAL
                          || kind == MERCATOR) ? dir_to_lon_height(kind, dx, dy, dz)
                                                                           : dir_to_plane(kind, dx, dy, dz);
            if (!p.ok) continue;
            x = p.x * f;
            y = p.y * f;
        }
        const double qx = x, qy = -y;  // lensfun's plane: y down
        const double r = std::hypot(qx, qy);
        if (!(r <= r_lim)) continue;
        const double p = poly_scale(coeffs, ncoeffs, r);
        xy[2 * i] = qx * p / norm + cx;
        xy[2 * i + 1] = qy * p / norm + cy;
        ok[i] = true;
    }
}

}  // namespace lenslab::lens
