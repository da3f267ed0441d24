// Pixel -> direction of the lens models with a closed form (their DirKernel, lenslab.lenses.core.protocol), and
// the bindings, registered into lenslab.cxx_kernels by register_lens_dirs(). The same operations in the same order
// as the models' NumPy steps (Lens.pixel_to_dir: pixel_to_uv, the model's uv_to_dir, the finiteness tests and
// clean; the equirect's and equidistant's sines and cosines from glibc's vector maths where it has them, within 4
// ulps), so a warp's exact map costs a fraction of the NumPy one; NumPy references in
// lenslab/lenses/formulas/reference.py (fisheye_dirs) and the models' own steps (Equirect._pixel_to_dir), held to
// them by tests/lenses/test_native_pixel_dirs.py and test_native_equirect_dirs.py. The equi-angular cube map's
// (eac_dirs) is in lens_cubemap.cpp, bound here.
// Built with every multiply and add rounded as written (CMakeLists.txt), as the NumPy code rounds them.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "lens_formulas.h"
#include "lens_kernels.h"
#include "lens_vmath.h"

namespace nb = nanobind;

namespace lenslab::lens {

using vmath::atan2_4;
using vmath::sin_cos4;
using vmath::tanh_cosh4;

namespace {

inline bool finite(double v) { return std::isfinite(v); }

// max(t, 0) as np.maximum takes it (a NaN stays NaN)
inline double at_least0(double t) { return t < 0.0 ? 0.0 : t; }

// Lens.pixel_to_uv of pixel (x, y): p = W, H, H / W first
inline void uv_of(double x, double y, const double* p, double& u, double& v) {
    u = x * 2.0;
    u /= p[0];
    u -= 1.0;
    v = y * 2.0;
    v /= p[1];
    v = 1.0 - v;
    if (p[0] != p[1]) v *= p[2];
}

// A fisheye pixel up to its plane point (Lens.pixel_to_uv, Fisheye._to_local, the plane scale). p = W, H, H / W,
// kind, plane scale, s_max^2 (with the rim slack), cx, cy, r_ref, local (0: the image centre and r_ref = 1)
struct Plane { double px, py, s2, r2; bool seen; };

inline Plane plane_of(double x, double y, const double* p) {
    const double c = p[4], s_max2 = p[5];
    double u, v;
    uv_of(x, y, p, u, v);  // Lens.pixel_to_uv, in its order
    if (p[9] != 0.0) {  // Fisheye._to_local
        u -= p[6];
        v -= p[7];
        u /= p[8];
        v /= p[8];
    }
    const double px = u * c, py = v * c;  // azimuthal.plane_to_dir
    const double r2 = u * u + v * v;
    // Lens.pixel_to_dir: a non-finite pixel has no ray; Fisheye.uv_to_dir: r <= s_max
    return {px, py, px * px + py * py, r2, r2 <= s_max2 && finite(x * x + y * y)};
}

// the direction (k px, k py, dz) where the pixel has a ray (clean(): finite), else zeros
inline void store_dir(const Plane& q, double k, double dz, double* d, bool* ok) {
    const double dx = q.px * k, dy = q.py * k;
    const bool good = q.seen && finite(dx * dx + dy * dy + dz * dz);
    *ok = good;
    d[0] = good ? dx : 0.0;
    d[1] = good ? dy : 0.0;
    d[2] = good ? dz : 0.0;
}

template <int64_t KIND>
void fisheye_loop(const double* xy, int64_t n, const double* p, double* d, bool* ok) {
    for (int64_t i = 0; i < n; ++i) {
        const Plane q = plane_of(xy[2 * i], xy[2 * i + 1], p);
        double k, dz;
        if constexpr (KIND == EQUISOLID) {  // sin(theta)/s = sqrt(1 - s^2/4), cos(theta) = 1 - s^2/2
            const double qq = 0.25 * q.s2;
            k = std::sqrt(at_least0(1.0 - qq));
            dz = qq * -2.0;
            dz += 1.0;
            dz = dz < -1.0 ? -1.0 : dz;  // s^2/4 a rounding past 1 at the back pole: still unit
        } else if constexpr (KIND == STEREOGRAPHIC) {
            const double q2 = 0.25 * q.s2;
            k = 1.0 / (1.0 + q2);
            dz = k * (1.0 - q2);
        } else {  // ORTHOGRAPHIC
            k = 1.0;
            dz = std::sqrt(at_least0(1.0 - q.s2));
        }
        store_dir(q, k, dz, d + 3 * i, ok + i);
    }
}

// equidistant: theta = s, sin(theta)/s (1 at s = 0) and cos(theta); with glibc's vector maths four at a time,
// every element the same way whatever its place in a call (a short block is padded), so a map does not depend
// on how the warp cut it into bands
template <>
void fisheye_loop<EQUIDISTANT>(const double* xy, int64_t n, const double* p, double* d, bool* ok) {
    for (int64_t i0 = 0; i0 < n; i0 += 4) {
        const int64_t m = std::min<int64_t>(4, n - i0);
        Plane q[4];
        double s[4] = {0.0, 0.0, 0.0, 0.0}, sn[4] = {0.0, 0.0, 0.0, 0.0}, cs[4] = {0.0, 0.0, 0.0, 0.0};
        bool any = false;
        for (int64_t j = 0; j < m; ++j) {
            q[j] = plane_of(xy[2 * (i0 + j)], xy[2 * (i0 + j) + 1], p);
            s[j] = std::sqrt(q[j].s2);
            any = any || q[j].seen;
        }
        if (!any) {  // outside the circle: no ray, no trigonometry (each lane's value is its own either way)
            for (int64_t j = 0; j < m; ++j) store_dir(q[j], 0.0, 0.0, d + 3 * (i0 + j), ok + i0 + j);
            continue;
        }
        sin_cos4(s, sn, cs);
        for (int64_t j = 0; j < m; ++j)
            store_dir(q[j], s[j] > 0.0 ? sn[j] / s[j] : 1.0, cs[j], d + 3 * (i0 + j), ok + i0 + j);
    }
}

// _Cylinder.uv_to_dir (longitude u F; lonlat.height_to_lat of KIND at v Fv; lonlat.lonlat_to_dir) through
// Lens.pixel_to_dir, four pixels at a time. p = W, H, H / W, code, F, Fv, the equal-area height limit (with slack)
template <int64_t KIND>
void cylinder_loop(const double* xy, int64_t n, const double* p, double* d, bool* ok) {
    const double F = p[4], Fv = p[5], y_lim = p[6];
    for (int64_t i0 = 0; i0 < n; i0 += 4) {
        const int64_t m = std::min<int64_t>(4, n - i0);
        double phi[4] = {0.0, 0.0, 0.0, 0.0}, y[4] = {0.0, 0.0, 0.0, 0.0}, sn[4], cs[4], s[4], c[4];
        bool seen[4] = {false, false, false, false};
        for (int64_t j = 0; j < m; ++j) {
            const double px = xy[2 * (i0 + j)], py = xy[2 * (i0 + j) + 1];
            double u, v;
            uv_of(px, py, p, u, v);
            phi[j] = u * F;
            y[j] = v * Fv;
            seen[j] = finite(px * px + py * py);
        }
        sin_cos4(phi, sn, cs);
        if constexpr (KIND == MERCATOR) {  // sin = tanh(y), cos = 1 / cosh(y)
            tanh_cosh4(y, s, c);
            for (int j = 0; j < 4; ++j) c[j] = 1.0 / c[j];
        }
        for (int64_t j = 0; j < m; ++j) {
            bool good = seen[j] && std::fabs(phi[j]) <= PI;
            if constexpr (KIND == CYLINDRICAL) {  // cos = 1 / sqrt(1 + y^2), sin = y cos
                c[j] = 1.0 / std::sqrt(1.0 + y[j] * y[j]);
                s[j] = y[j] * c[j];
                good = good && finite(y[j]);
            } else if constexpr (KIND == EQUAL_AREA_CYLINDRICAL) {  // sin = y clipped to [-1, 1]
                s[j] = std::isnan(y[j]) ? y[j] : std::min(std::max(y[j], -1.0), 1.0);
                c[j] = std::sqrt(at_least0(1.0 - s[j] * s[j]));
                good = good && std::fabs(y[j]) <= y_lim;
            } else {
                good = good && finite(y[j]);
            }
            const double dx = sn[j] * c[j], dy = s[j], dz = cs[j] * c[j];
            good = good && finite(dx * dx + dy * dy + dz * dz);
            double* o = d + 3 * (i0 + j);
            ok[i0 + j] = good;
            o[0] = good ? dx : 0.0;
            o[1] = good ? dy : 0.0;
            o[2] = good ? dz : 0.0;
        }
    }
}

}  // namespace

// Pannini.uv_to_dir through Lens.pixel_to_dir, four pixels at a time: with x = u x_f, k = x^2 / (d + 1)^2, the root of
// 1 + k (1 - d^2), cos phi from it, S = (d + 1)(k + 1) / (d + root), phi = atan2(x, S cos phi), the latitude's tangent
// v x_f / (1 + (1 - vcomp)(S - 1)); d = (sin phi, tan, cos phi) cos(latitude). p = W, H, H / W, d, x_f, (d + 1)^2,
// 1 - d^2, the largest |phi| (with its slack), 1 - vcomp
void pannini_dirs(const double* xy, int64_t n, const double* p, double* d, bool* ok) {
    const double dd = p[3], x_f = p[4], dp2 = p[5], omd2 = p[6], phi_lim = p[7], keep = p[8];
    for (int64_t i0 = 0; i0 < n; i0 += 4) {
        const int64_t m = std::min<int64_t>(4, n - i0);
        double x[4] = {0.0, 0.0, 0.0, 0.0}, y[4] = {0.0, 0.0, 0.0, 0.0}, sc[4] = {1.0, 1.0, 1.0, 1.0};
        double S[4] = {1.0, 1.0, 1.0, 1.0}, phi[4], sn[4], cs[4];
        bool good[4] = {false, false, false, false};
        for (int64_t j = 0; j < m; ++j) {
            const double px = xy[2 * (i0 + j)], py = xy[2 * (i0 + j) + 1];
            double u, v;
            uv_of(px, py, p, u, v);
            x[j] = u * x_f;
            y[j] = v * x_f;
            const double k = x[j] * x[j] / dp2;
            const double disc = 1.0 + k * omd2;
            const double root = std::sqrt(at_least0(disc));
            const double clon = (root - k * dd) / (k + 1.0);
            S[j] = (dd + 1.0) * (k + 1.0) / (dd + root);
            sc[j] = S[j] * clon;
            good[j] = disc >= 0.0 && finite(px * px + py * py);
        }
        atan2_4(phi, x, sc);
        sin_cos4(phi, sn, cs);
        for (int64_t j = 0; j < m; ++j) {
            const double tan_t = y[j] / (1.0 + keep * (S[j] - 1.0));
            const double c = 1.0 / std::sqrt(1.0 + tan_t * tan_t);
            const double dx = sn[j] * c, dy = tan_t * c, dz = cs[j] * c;
            const bool seen = good[j] && std::fabs(phi[j]) <= phi_lim && finite(tan_t)
                              && finite(dx * dx + dy * dy + dz * dz);
            double* o = d + 3 * (i0 + j);
            ok[i0 + j] = seen;
            o[0] = seen ? dx : 0.0;
            o[1] = seen ? dy : 0.0;
            o[2] = seen ? dz : 0.0;
        }
    }
}

// Equirect._pixel_to_dir, four pixels at a time: the longitude and latitude linear in x and y (the whole sphere in
// the conventions' exact forms and order), d = (sin lon cos lat, sin lat, cos lon cos lat) with the sines and cosines
// from glibc's vector maths (a short block is padded: every element the same way wherever it falls), the exact
// poles at the top and bottom edges, then Lens.in_image and clean. p = W, H, whole sphere (0 or 1), lon0, lon1,
// lat0, lat1 (radians), pole at the top (0 or 1), pole at the bottom (0 or 1)
void equirect_dirs(const double* xy, int64_t n, const double* p, double* d, bool* ok) {
    const double W = p[0], H = p[1], lon0 = p[3], lon1 = p[4], lat0 = p[5], lat1 = p[6];
    const bool whole = p[2] != 0.0, top = p[7] != 0.0, bottom = p[8] != 0.0;
    for (int64_t i0 = 0; i0 < n; i0 += 4) {
        const int64_t m = std::min<int64_t>(4, n - i0);
        double phi[4] = {0.0, 0.0, 0.0, 0.0}, theta[4] = {0.0, 0.0, 0.0, 0.0}, sp[4], cp[4], st[4], ct[4];
        for (int64_t j = 0; j < m; ++j) {
            const double x = xy[2 * (i0 + j)], y = xy[2 * (i0 + j) + 1];
            if (whole) {
                phi[j] = 2.0 * x;
                phi[j] /= W;
                phi[j] -= 1.0;
                phi[j] *= PI;
                theta[j] = 2.0 * y;
                theta[j] /= H;
                theta[j] = 1.0 - theta[j];
                theta[j] *= PI / 2;
            } else {
                phi[j] = x / W;
                phi[j] *= lon1 - lon0;
                phi[j] += lon0;
                theta[j] = y / H;
                theta[j] *= lat1 - lat0;
                theta[j] = lat1 - theta[j];
            }
        }
        sin_cos4(phi, sp, cp);
        sin_cos4(theta, st, ct);
        for (int64_t j = 0; j < m; ++j) {
            const double x = xy[2 * (i0 + j)], y = xy[2 * (i0 + j) + 1];
            double dx = sp[j] * ct[j], dy = st[j], dz = cp[j] * ct[j];
            if ((top && y == 0.0) || (bottom && y == H)) {  // exact poles, whatever cos(pi/2) rounds to
                dx = 0.0;
                dy = y == 0.0 && top ? 1.0 : -1.0;
                dz = 0.0;
            }
            const bool good = x >= 0.0 && x <= W && y >= 0.0 && y <= H && finite(dx * dx + dy * dy + dz * dz);
            double* o = d + 3 * (i0 + j);
            ok[i0 + j] = good;
            o[0] = good ? dx : 0.0;
            o[1] = good ? dy : 0.0;
            o[2] = good ? dz : 0.0;
        }
    }
}

// cylinder pixels -> unit directions (0 and false where the lens has no ray)
void cylinder_dirs(const double* xy, int64_t n, const double* p, double* d, bool* ok) {
    with_cylinder_kind(int64_t(p[3]), "cylinder_dirs",
                       [&](auto k) { cylinder_loop<decltype(k)::value>(xy, n, p, d, ok); });
}

// perspective pixels -> unit directions (Perspective.uv_to_dir: every finite pixel has a ray). p = W, H, H / W, t, tv
void perspective_dirs(const double* xy, int64_t n, const double* p, double* d, bool* ok) {
    const double t = p[3], tv = p[4];
    for (int64_t i = 0; i < n; ++i) {
        const double x = xy[2 * i], y = xy[2 * i + 1];
        double u, v;
        uv_of(x, y, p, u, v);
        double dx = u * t, dy = v * tv;
        double dz = dx * dx;  // z = 1 / sqrt(x^2 + y^2 + 1), then x, y scaled by it
        dz += dy * dy;
        dz += 1.0;
        dz = std::sqrt(dz);
        dz = 1.0 / dz;
        dx *= dz;
        dy *= dz;
        const bool good = finite(x * x + y * y) && finite(dx * dx + dy * dy + dz * dz);
        ok[i] = good;
        d[3 * i] = good ? dx : 0.0;
        d[3 * i + 1] = good ? dy : 0.0;
        d[3 * i + 2] = good ? dz : 0.0;
    }
}

// fisheye pixels -> unit directions (0 and false where the lens has no ray)
void fisheye_dirs(const double* xy, int64_t n, const double* p, double* d, bool* ok) {
    with_fisheye_kind(int64_t(p[3]), "fisheye_dirs",
                      [&](auto k) { fisheye_loop<decltype(k)::value>(xy, n, p, d, ok); });
}

// a fisheye turned in the camera (the little planet): fisheye_dirs, then d M with M (row-major) after the fisheye's
// 10 parameters, as NumPy's matmul (exact for the axis permutations the models use); in blocks that stay in the cache
void turned_fisheye_dirs(const double* xy, int64_t n, const double* p, double* d, bool* ok) {
    constexpr int64_t B = 256;
    const double* M = p + 10;
    for (int64_t i0 = 0; i0 < n; i0 += B) {
        const int64_t m = std::min(B, n - i0);
        fisheye_dirs(xy + 2 * i0, m, p, d + 3 * i0, ok + i0);
        for (int64_t j = 0; j < m; ++j) {
            double* o = d + 3 * (i0 + j);
            const double a = o[0], b = o[1], c = o[2];
            for (int k = 0; k < 3; ++k) o[k] = a * M[k] + b * M[3 + k] + c * M[6 + k];
        }
    }
}

}  // namespace lenslab::lens

namespace {

template <typename T> using In = nb::ndarray<const T, nb::c_contig, nb::device::cpu>;
template <typename T> using Out = nb::ndarray<T, nb::c_contig, nb::device::cpu>;

void need(bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(what);
}

}  // namespace

using DirFn = void (*)(const double*, int64_t, const double*, double*, bool*);

// binds one DirKernel function: fn(xy, params, d, ok), `nparams` parameters, outputs written in place
template <DirFn FN, size_t NPARAMS>
void bind_dirs(nb::module_& m, const char* name, const char* doc) {
    m.def(name, [](In<double> xy, In<double> p, Out<double> d, Out<bool> ok) {
        need(xy.size() % 2 == 0, "pixels must be rows of (x, y)");
        const size_t n = xy.size() / 2;
        need(d.size() == 3 * n && ok.size() == n, "outputs must hold one row per pixel");
        need(p.size() == NPARAMS, "wrong number of lens parameters");
        FN(xy.data(), int64_t(n), p.data(), d.data(), ok.data());
    }, nb::arg("xy"), nb::arg("params"), nb::arg("d").noconvert(), nb::arg("ok").noconvert(),
       nb::call_guard<nb::gil_scoped_release>(), doc);
}

void register_lens_dirs(nb::module_& m) {
    bind_dirs<lenslab::lens::perspective_dirs, 5>(
        m, "perspective_dirs",
        "Perspective pixels (any length; non-finite ones invalid) -> unit directions (the lens's DirKernel).");
    bind_dirs<lenslab::lens::fisheye_dirs, 10>(
        m, "fisheye_dirs",
        "Fisheye pixels (any length; non-finite ones invalid) -> unit directions (the lens's DirKernel).");
    bind_dirs<lenslab::lens::turned_fisheye_dirs, 19>(
        m, "turned_fisheye_dirs",
        "Pixels of a fisheye turned in the camera (any length; non-finite ones invalid) -> unit directions.");
    bind_dirs<lenslab::lens::pannini_dirs, 9>(
        m, "pannini_dirs",
        "Pannini pixels (any length; non-finite ones invalid) -> unit directions (the lens's DirKernel).");
    bind_dirs<lenslab::lens::equirect_dirs, 9>(
        m, "equirect_dirs",
        "Equirect pixels (any length; non-finite ones invalid) -> unit directions (the lens's DirKernel).");
    bind_dirs<lenslab::lens::cylinder_dirs, 7>(
        m, "cylinder_dirs",
        "Cylinder pixels (any length; non-finite ones invalid) -> unit directions (the lens's DirKernel).");
    bind_dirs<lenslab::lens::eac_dirs, 60>(
        m, "eac_dirs",
        "Equi-angular cube map pixels (any length; non-finite ones invalid) -> unit directions (the lens's DirKernel).");
}
