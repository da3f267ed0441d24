// The one safeguarded Newton of the lens models' numerically inverted sides, one element at a time: the steps
// and settings of lenslab.lenses.formulas.solve.invert_increasing (its NumPy reference), on the radial maps
// the models need. Starting guesses come from a table of the inverse (solve.inverse_table).
#pragma once

#include <cmath>
#include <cstdint>

#include "lens_formulas.h"

namespace lenslab::lens {

// the radial maps (lenslab.lenses.formulas.solve: DIVISION, DIVISION_RECIPROCAL, BROWN, TAN_FISHEYE, RATIONAL, OCAM)
enum Radial : int64_t { DIVISION = 0, DIVISION_RECIPROCAL = 1, BROWN = 2, TAN_FISHEYE = 3, RATIONAL = 4, OCAM = 5 };

// the solver's settings (solve.kernel_settings)
struct Solver { double tol, res_tol, rel_ulps; int64_t max_iter; };

// coefficients of a radial map: a (na of them) and b (nb of them)
struct Coeffs { const double* a; int64_t na; const double* b; int64_t nb; };

struct VD { double v, d; };

// R(r) and dR/d(r^2) of OpenCV's rational radial factor (1 + a1 r^2 + .. + a4 r^8) / (1 + b1 r^2 + b2 r^4 + b3 r^6)
inline VD rational_radial(double r, const double* a, const double* b) {
    const double s = r * r;
    const double num = 1.0 + s * (a[0] + s * (a[1] + s * (a[2] + s * a[3])));
    const double dnum = a[0] + s * (2.0 * a[1] + s * (3.0 * a[2] + s * 4.0 * a[3]));
    const double den = 1.0 + s * (b[0] + s * (b[1] + s * b[2]));
    const double dden = b[0] + s * (2.0 * b[1] + s * 3.0 * b[2]);
    return {num / den, (dnum * den - num * dden) / (den * den)};
}

// value and derivative of radial map `kind` at x
inline VD radial_value(int64_t kind, double x, const Coeffs& c) {
    if (kind == RATIONAL) {
        VD R = rational_radial(x, c.a, c.b);
        return {x * R.v, R.v + 2.0 * x * x * R.d};
    }
    if (kind == OCAM) {  // rho cos(t) + pol(rho) sin(t): the sign of angle(rho) - t; b = (cos t, sin t)
        double p = 0.0, dp = 0.0;
        for (int64_t j = c.na - 1; j >= 0; --j) {
            dp = dp * x + p;
            p = p * x + c.a[j];
        }
        return {x * c.b[0] + p * c.b[1], c.b[0] + dp * c.b[1]};
    }
    const double p0 = c.a[0], p1 = c.a[1];
    const double s = x * x;
    if (kind == DIVISION || kind == DIVISION_RECIPROCAL) {
        const double den = 1.0 + s * (p0 + p1 * s);
        const double num = 1.0 - s * (p0 + 3.0 * p1 * s);
        if (kind == DIVISION) {
            if (den <= 0.0) return {INF, 0.0};  // at and past a pole r_u is +inf
            return {x / den, num / (den * den)};
        }
        if (x == 0.0) return {-INF, INF};
        return {-den / x, num / s};
    }
    if (kind == BROWN) return {x * (1.0 + s * (p0 + p1 * s)), 1.0 + s * (3.0 * p0 + 5.0 * p1 * s)};
    // TAN_FISHEYE: the tan-fold fisheye's angle from the axis, kept increasing past the fold
    const double t = std::tan(x * p0);
    const double st = std::sin(t), ct = std::cos(t);
    const double y = x * st;
    double psi = std::atan2(y, ct);
    if (y < 0.0) psi += 2.0 * PI;
    return {psi, (st * ct + x * p0 * (1.0 + t * t)) / (ct * ct + y * y)};
}

struct Root { double x; bool ok; int64_t its; };

// Safeguarded Newton for one element on [0, hi]
inline Root solve_one(int64_t kind, const Coeffs& c, double t, double hi, double x0, const Solver& s) {
    double lo_b = 0.0, hi_b = hi;
    double x = std::fmin(std::fmax(x0, lo_b), hi_b);
    double last_step = INF;
    for (int64_t it = 1; it <= s.max_iter; ++it) {
        VD f = radial_value(kind, x, c);
        const double res = f.v - t;
        if (res < 0.0) lo_b = x;
        else hi_b = x;
        double xn = x - res / f.d;
        const double step = std::fabs(xn - x);
        const bool small = step <= s.tol;
        const bool far = std::fabs(res) > s.res_tol * std::fmax(1.0, std::fabs(t));
        const bool bad = !(xn >= lo_b && xn <= hi_b) || (small && far) || step > 0.5 * last_step;
        if (bad) xn = 0.5 * (lo_b + hi_b);
        const bool at_rounding = std::fabs(res) <= s.rel_ulps * std::fabs(t);
        const bool done = (small && !bad) || at_rounding || (hi_b - lo_b <= s.tol);
        if (at_rounding) xn = x;
        last_step = std::fabs(xn - x);
        x = xn;
        if (done) return {x, true, it};
    }
    return {x0, false, s.max_iter};
}

// Linear interpolation in the table of the inverse (uniform in t, or in sqrt(t)); beyond it (or NaN), its last entry
inline double table_guess(double t, const double* table, int64_t len, double step, bool sqrt_map) {
    const double g = sqrt_map ? std::sqrt(t) : t;
    const double q = g / step;
    const int64_t n = len - 1;
    if (!(q < double(n))) return table[n];
    const int64_t j = int64_t(q);
    const double w = q - double(j);
    return table[j] + w * (table[j + 1] - table[j]);
}

}  // namespace lenslab::lens
