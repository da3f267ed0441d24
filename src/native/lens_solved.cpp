// The solved sides of the lens models (lens_kernels.h): the tan-fold fisheye's direction -> plane, the division
// model's unbending and Brown's bending (one safeguarded Newton per radius, lens_solve.h), the calibrated models'
// unprojection through OpenCV's undistortion (the radial solve, then a 2-D Newton) and OCamCalib's projection (its
// polynomial solved for the image radius), built with every multiply and add rounded as written (CMakeLists.txt).
// NumPy references: lenslab/lenses/formulas/reference.py (tests/lenses/test_native_lens_kernels.py).
// The tan-fold fisheye stays first: the order of a file's functions numbers its constants, and with another first,
// GCC gave two constants of calibrated_unproject each other's register (the same operations; docs/design.md).
#include "lens_calibrated_steps.h"
#include "lens_kernels.h"
#include "lens_pixel_steps.h"

#include <algorithm>
#include <cmath>

namespace lenslab::lens {

namespace {

inline bool finite(double v) { return std::isfinite(v); }

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

}  // namespace lenslab::lens
