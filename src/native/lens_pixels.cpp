// Direction -> pixel of the fisheye (and of the little planet, a stereographic fisheye turned to look down, and of
// two fisheyes back to back), the cylinders (central, Lambert's equal-area, Mercator), the sinusoidal map, Pannini
// and the Brown-distorted and swirled pinholes: their PixelKernel (lens_kernels.h), the steps of the model's NumPy
// dir_to_pixel (normalise, dir_to_uv, uv_to_pixel, snap_to_image) in their order, built with every multiply and add
// rounded as written (CMakeLists.txt). The arc tangents, the logarithm of Mercator's asinh and the swirl's sines and
// cosines come from glibc's vector maths four at a time where it has them (lens_vmath.h, within 4 ulps of libm);
// every element takes the same path whatever its place in a call (a short block is padded), so a map does not depend
// on how the warp cut it into bands. Held to the models' NumPy steps by tests/lenses/test_native_lens_kernels.py and
// to the published formulas by tests/lenses/test_native_projection_pixels.py.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "lens_formulas.h"
#include "lens_kernels.h"
#include "lens_pixel_steps.h"
#include "lens_vmath.h"


namespace lenslab::lens {

using vmath::atan2_4;
using vmath::sin_cos4;

namespace {

// asinh(a[j]) of four values, written over them, as sign(a) log(|a| + sqrt(a^2 + 1)) with glibc's vector logarithm
// (three times faster than its vector asinh): within a few ulps of 1 of it, the same to 1e-13 px of a map; the
// quotient's overflow past 1e154 gives inf where asinh gives 355, both far beyond any image
inline void asinh_4(double* a) {
    double g[4];
    for (int j = 0; j < 4; ++j) {
        const double m = std::fabs(a[j]);
        g[j] = m + std::sqrt(m * m + 1.0);
    }
    vmath::log4(g);
    for (int j = 0; j < 4; ++j) a[j] = std::copysign(g[j], a[j]);
}

// Up to four directions from i0 (m of them), normalised (Lens.dir_to_pixel) and turned by R (row-major: the
// lens sees R d), into x, y, z; their outputs cleared; `good` false for zero and non-finite ones. Padding and
// unseen lanes hold +z.
inline bool load4(const double* d, int64_t i0, int64_t m, const double* R, double* x, double* y, double* z,
                  bool* good, double* xy, bool* ok) {
    bool any = false;
    for (int j = 0; j < 4; ++j) {
        x[j] = 0.0;
        y[j] = 0.0;
        z[j] = 1.0;
        good[j] = false;
    }
    for (int64_t j = 0; j < m; ++j) {
        clear2(i0 + j, xy, ok);
        double a, b, c;
        if (!unit_dir(d, i0 + j, a, b, c)) continue;
        if (R) {  // d @ R.T, as NumPy's matmul: exact for the axis permutations the models use
            x[j] = a * R[0] + b * R[1] + c * R[2];
            y[j] = a * R[3] + b * R[4] + c * R[5];
            z[j] = a * R[6] + b * R[7] + c * R[8];
        } else {
            x[j] = a;
            y[j] = b;
            z[j] = c;
        }
        good[j] = true;
        any = true;
    }
    return any;
}

// Fisheye.dir_to_uv of one unit direction (azimuthal.dir_to_plane of the mapping KIND with rho^2 = x^2 + y^2, rho and,
// equidistant, theta = atan2(rho, z); over the plane scale ps; the rim test s / ps <= s_lim; the orthographic
// mapping's seen test), before Fisheye._from_local: false where the lens does not see it
template <int64_t KIND>
inline bool fisheye_uv(double x, double y, double dz, double rho2, double r, double theta, double ps, double s_lim,
                       double& u, double& v) {
    double s, k;
    if constexpr (KIND == EQUIDISTANT) {  // s = theta
        s = theta;
        k = r > 0.0 ? s / r : 1.0;
    } else if constexpr (KIND == EQUISOLID) {  // s = 2 rho / sqrt(2 (1 + dz)); behind, sqrt(2 (1 - dz))
        if (dz < 0.0) {
            s = std::sqrt(2.0 * (1.0 - dz));
            k = s / r;
        } else {
            k = std::sqrt(2.0 * (1.0 + dz));
            k = 2.0 / k;
            s = k * r;
        }
    } else if constexpr (KIND == STEREOGRAPHIC) {  // s = 2 rho / (1 + dz); behind, 2 (1 - dz) / rho
        if (dz < 0.0) {
            const double num = 2.0 * (1.0 - dz);
            s = num / r;
            k = num / rho2;
        } else {
            k = 2.0 / (1.0 + dz);
            s = k * r;
        }
    } else {  // ORTHOGRAPHIC
        k = 1.0;
        s = r;
    }
    if (r == 0.0 && dz < 0.0) {  // the back pole: every azimuth at once, (s, 0)
        u = s;
        v = 0.0;
    } else {
        u = x * k;
        v = y * k;
    }
    u /= ps;
    v /= ps;
    if (!(s / ps <= s_lim)) return false;
    if constexpr (KIND == ORTHOGRAPHIC) return dz >= 0.0;
    return true;
}

// rho^2, rho and (equidistant) theta of four unit directions, theta four at a time
template <int64_t KIND>
inline void polar4(const double* x, const double* y, const double* z, double* rho2, double* rho, double* theta) {
    for (int j = 0; j < 4; ++j) {
        rho2[j] = x[j] * x[j] + y[j] * y[j];
        rho[j] = std::sqrt(rho2[j]);
        theta[j] = 0.0;
    }
    if constexpr (KIND == EQUIDISTANT) atan2_4(theta, rho, z);
}

// Fisheye.dir_to_uv through Lens.dir_to_pixel (with Fisheye._from_local), then the pixel
template <int64_t KIND>
void fisheye_loop(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    const double w = p[0], h = p[1], aspect = p[2], ps = p[4], s_lim = p[5], cx = p[7], cy = p[8], r_ref = p[9];
    const double slack = p[10];
    const bool local = p[6] != 0.0;
    const double* R = p[11] != 0.0 ? p + 12 : nullptr;
    for (int64_t i0 = 0; i0 < n; i0 += 4) {
        const int64_t m = std::min<int64_t>(4, n - i0);
        double x[4], y[4], z[4], rho2[4], rho[4], theta[4];
        bool good[4];
        if (!load4(d, i0, m, R, x, y, z, good, xy, ok)) continue;
        polar4<KIND>(x, y, z, rho2, rho, theta);
        for (int64_t j = 0; j < m; ++j) {
            double u, v;
            if (!good[j] || !fisheye_uv<KIND>(x[j], y[j], z[j], rho2[j], rho[j], theta[j], ps, s_lim, u, v)) continue;
            if (local) {
                u *= r_ref;
                v *= r_ref;
                u += cx;
                v += cy;
            }
            uv_pixel(i0 + j, u, v, w, h, aspect, slack, xy, ok);
        }
    }
}

// DualFisheye.dir_to_pixel: the direction from the lens whose axis is nearer (the back lens, x and z negated, for
// z < 0), that fisheye's dir_to_uv, the position in its half, kept off the shared edge in the left half, the image
// test. p = W, H, the half width, mapping code, plane scale, largest s over it, the front lens's left edge, edge slack,
// half / H, the largest x of the left half
template <int64_t KIND>
void dual_fisheye_loop(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    const double w = p[0], h = p[1], half = p[2], ps = p[4], s_lim = p[5], front_x0 = p[6], slack = p[7];
    const double ky = p[8], left_max = p[9];
    for (int64_t i0 = 0; i0 < n; i0 += 4) {
        const int64_t m = std::min<int64_t>(4, n - i0);
        double x[4], y[4], z[4], rho2[4], rho[4], theta[4];
        bool good[4], back[4];
        if (!load4(d, i0, m, nullptr, x, y, z, good, xy, ok)) continue;
        for (int j = 0; j < 4; ++j) {
            back[j] = z[j] < 0.0;
            if (back[j]) {  // half a turn about +y: exact
                x[j] = -x[j];
                z[j] = -z[j];
            }
        }
        polar4<KIND>(x, y, z, rho2, rho, theta);
        for (int64_t j = 0; j < m; ++j) {
            double u, v;
            if (!good[j] || !fisheye_uv<KIND>(x[j], y[j], z[j], rho2[j], rho[j], theta[j], ps, s_lim, u, v)) continue;
            const double x0 = back[j] ? half - front_x0 : front_x0;
            double px = u + 1.0;
            px *= 0.5;
            px *= half;
            px += x0;
            double py = v * ky;
            py = 1.0 - py;
            py *= 0.5;
            py *= h;
            if (x0 == 0.0) px = std::min(px, left_max);  // the shared edge belongs to the right half
            if (!(px >= -slack && px <= w + slack && py >= -slack && py <= h + slack)) continue;
            xy[2 * (i0 + j)] = std::min(std::max(px, 0.0), w);
            xy[2 * (i0 + j) + 1] = std::min(std::max(py, 0.0), h);
            ok[i0 + j] = true;
        }
    }
}

// _Cylinder.dir_to_uv (lonlat.dir_to_lonlat, lonlat.lat_to_height of KIND, over F and Fv, the longitude test), then
// the pixel
template <int64_t KIND>
void cylinder_loop(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    const double w = p[0], h = p[1], aspect = p[2], F = p[4], Fv = p[5], lon_lim = p[6], slack = p[7];
    for (int64_t i0 = 0; i0 < n; i0 += 4) {
        const int64_t m = std::min<int64_t>(4, n - i0);
        double x[4], y[4], z[4], phi[4], c[4], t[4];
        bool good[4];
        if (!load4(d, i0, m, nullptr, x, y, z, good, xy, ok)) continue;
        atan2_4(phi, x, z);
        if constexpr (KIND != EQUAL_AREA_CYLINDRICAL) {  // the height s / c (0 at the poles, which are unseen)
            for (int j = 0; j < 4; ++j) {  // hypot(x, z) of a unit direction: no overflow, within an ulp of it
                c[j] = std::sqrt(x[j] * x[j] + z[j] * z[j]);
                t[j] = y[j] / c[j];  // unused where c = 0 (the poles, unseen): no branch, four at a time
            }
            if constexpr (KIND == MERCATOR) asinh_4(t);  // atanh(s) = asinh(s / c): no 1 - s near the poles
        }
        for (int64_t j = 0; j < m; ++j) {
            if (!good[j]) continue;
            double v;
            if constexpr (KIND == EQUAL_AREA_CYLINDRICAL) {
                v = y[j];
            } else {
                if (!(c[j] > 0.0)) continue;
                v = t[j];
            }
            if (!(std::fabs(phi[j]) <= lon_lim)) continue;
            uv_pixel(i0 + j, phi[j] / F, v / Fv, w, h, aspect, slack, xy, ok);
        }
    }
}

}  // namespace

// Sinusoidal.dir_to_uv (u = atan2(dx, dz) c / pi with c = hypot(dx, dz), v = atan2(dy, c) / pi), then the pixel.
// p = W, H, H / W, edge slack
void sinusoidal_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    const double w = p[0], h = p[1], aspect = p[2], slack = p[3];
    for (int64_t i0 = 0; i0 < n; i0 += 4) {
        const int64_t m = std::min<int64_t>(4, n - i0);
        double x[4], y[4], z[4], c[4], phi[4], theta[4];
        bool good[4];
        if (!load4(d, i0, m, nullptr, x, y, z, good, xy, ok)) continue;
        for (int j = 0; j < 4; ++j) c[j] = std::sqrt(x[j] * x[j] + z[j] * z[j]);  // hypot of a unit direction
        atan2_4(phi, x, z);
        atan2_4(theta, y, c);
        for (int64_t j = 0; j < m; ++j) {
            if (!good[j]) continue;
            double u = phi[j] * c[j];
            u /= PI;
            uv_pixel(i0 + j, u, theta[j] / PI, w, h, aspect, slack, xy, ok);
        }
    }
}

// Pannini.dir_to_uv (S = (d + 1) / (d + cos phi) with cos phi = dz / c, c = hypot(dx, dz); u = (dx / c) S / x_f,
// v = (dy / c) (1 + (1 - vcomp) (S - 1)) / x_f; seen within the edge longitude, off the poles, for S > 0), then the
// pixel. p = W, H, H / W, d, x_f, cos of the edge longitude (with its slack), 1 - vcomp, edge slack
void pannini_pixels(const double* dirs, int64_t n, const double* p, double* xy, bool* ok) {
    const double w = p[0], h = p[1], aspect = p[2], d = p[3], x_f = p[4], cos_edge = p[5], keep = p[6];
    const double slack = p[7];
    for (int64_t i = 0; i < n; ++i) {
        clear2(i, xy, ok);
        double x, y, z;
        if (!unit_dir(dirs, i, x, y, z)) continue;
        const double c = std::sqrt(x * x + z * z);  // hypot of a unit direction
        const double inv_c = c > 0.0 ? 1.0 / c : 0.0;
        const double cphi = z * inv_c;
        double S = d + cphi;
        if (!(cphi >= cos_edge && c > 0.0 && S > 0.0)) continue;
        S = (d + 1.0) / S;
        double u = x * inv_c;
        u *= S;
        u /= x_f;
        double v = y * inv_c;
        v *= 1.0 + keep * (S - 1.0);
        v /= x_f;
        if (std::isfinite(u) && std::isfinite(v)) uv_pixel(i, u, v, w, h, aspect, slack, xy, ok);
    }
}

// Perspective.dir_to_uv, then Swirl.unbend (rotate_by_radius by -amount: (u + i v) exp(i k), k = -amount |(u, v)|,
// as NumPy's complex product), then the pixel, four directions at a time. p = W, H, H / W, t, t_v, -amount, edge slack
void swirl_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    const double w = p[0], h = p[1], aspect = p[2], t = p[3], tv = p[4], amount = p[5], slack = p[6];
    for (int64_t i0 = 0; i0 < n; i0 += 4) {
        const int64_t m = std::min<int64_t>(4, n - i0);
        double u[4] = {0.0, 0.0, 0.0, 0.0}, v[4] = {0.0, 0.0, 0.0, 0.0}, k[4] = {0.0, 0.0, 0.0, 0.0}, c[4], s[4];
        bool good[4] = {false, false, false, false};
        for (int64_t j = 0; j < m; ++j) {
            clear2(i0 + j, xy, ok);
            good[j] = pinhole_uv(d, i0 + j, t, tv, u[j], v[j]);
            if (!good[j]) continue;
            k[j] = u[j] * u[j];
            k[j] += v[j] * v[j];
            k[j] = std::sqrt(k[j]);
            k[j] *= amount;
        }
        sin_cos4(k, s, c);
        for (int64_t j = 0; j < m; ++j) {
            if (!good[j]) continue;
            uv_pixel(i0 + j, c[j] * u[j] - s[j] * v[j], c[j] * v[j] + s[j] * u[j], w, h, aspect, slack, xy, ok);
        }
    }
}

void fisheye_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    with_fisheye_kind(int64_t(p[3]), "fisheye_pixels",
                      [&](auto k) { fisheye_loop<decltype(k)::value>(d, n, p, xy, ok); });
}

void dual_fisheye_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    with_fisheye_kind(int64_t(p[3]), "dual_fisheye_pixels",
                      [&](auto k) { dual_fisheye_loop<decltype(k)::value>(d, n, p, xy, ok); });
}

void cylinder_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    with_cylinder_kind(int64_t(p[3]), "cylinder_pixels",
                       [&](auto k) { cylinder_loop<decltype(k)::value>(d, n, p, xy, ok); });
}

// Perspective.dir_to_uv, then Brown.unbend (u, v) (1 + s (k1 + k2 s)) with s = u^2 + v^2 and its fold test, then the
// pixel
void brown_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    const double w = p[0], h = p[1], aspect = p[2], t = p[3], tv = p[4], k1 = p[5], k2 = p[6], fold2 = p[7];
    const double slack = p[8];
    for (int64_t i = 0; i < n; ++i) {
        clear2(i, xy, ok);
        double u, v;
        if (!pinhole_uv(d, i, t, tv, u, v)) continue;
        const double s = u * u + v * v;
        if (!(s < fold2)) continue;
        const double poly = 1.0 + s * (k1 + k2 * s);
        uv_pixel(i, u * poly, v * poly, w, h, aspect, slack, xy, ok);
    }
}

}  // namespace lenslab::lens
