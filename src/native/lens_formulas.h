// The lens models' formulas, one direction or plane point at a time: the C++ twins of the NumPy functions in
// lenslab/lenses/formulas/ (azimuthal.py, lonlat.py, calibrated.py, radial.py), inlined into the fused
// kernels of src/native/lens_*.cpp. The same operations in the same order as the NumPy code
// (tests/lenses/test_native_lens_kernels.py holds each kernel to its NumPy reference).
#pragma once

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace lenslab::lens {

constexpr double PI = 3.14159265358979323846;
constexpr double INF = HUGE_VAL;

// projection codes: lenslab/lenses/formulas/kinds.py (the module exports them and a test compares)
enum Kind : int64_t {
    RECTILINEAR = 0, EQUIRECTANGULAR = 1, CYLINDRICAL = 2, EQUIDISTANT = 3, EQUISOLID = 4, STEREOGRAPHIC = 5,
    ORTHOGRAPHIC = 6, THOBY = 7, UNIFIED = 8, DOUBLE_SPHERE = 9, EUCM = 10, FOV = 11, EQUAL_AREA_CYLINDRICAL = 12,
    MERCATOR = 13,
};
constexpr int64_t PINHOLE = RECTILINEAR;

// A mapping code as a compile-time constant: body runs with std::integral_constant<int64_t, K> for the K of KINDS
// equal to code, so that a kernel's loop is compiled once per mapping; another code is a std::invalid_argument
// "<what>: not a <family> code"
template <int64_t... KINDS, class Body>
inline void with_kind(int64_t code, const char* what, const char* family, Body&& body) {
    if (!((code == KINDS && (body(std::integral_constant<int64_t, KINDS>{}), true)) || ...))
        throw std::invalid_argument(std::string(what) + ": not a " + family + " code");
}

// the fisheye mappings (EQUIDISTANT, EQUISOLID, STEREOGRAPHIC, ORTHOGRAPHIC) and the cylinders
template <class Body>
inline void with_fisheye_kind(int64_t code, const char* what, Body&& body) {
    with_kind<EQUIDISTANT, EQUISOLID, STEREOGRAPHIC, ORTHOGRAPHIC>(code, what, "fisheye mapping", body);
}
template <class Body>
inline void with_cylinder_kind(int64_t code, const char* what, Body&& body) {
    with_kind<CYLINDRICAL, EQUAL_AREA_CYLINDRICAL, MERCATOR>(code, what, "cylinder", body);
}
constexpr double THOBY_K1 = 1.47, THOBY_K2 = 0.713;

struct P2 { double x, y; bool ok; };
struct P3 { double x, y, z; bool ok; };

// Unit direction -> (x, y, ok) on the plane at unit focal length of an azimuthal mapping
// (lenslab.lenses.formulas.azimuthal.dir_to_plane).
inline P2 dir_to_plane(int64_t kind, double dx, double dy, double dz) {
    const double rho = std::sqrt(dx * dx + dy * dy);
    double k;
    if (kind == EQUIDISTANT) {
        if (!(rho > 0.0)) return {0.0, 0.0, dz > 0.0};
        k = std::atan2(rho, dz) / rho;
    } else if (kind == EQUISOLID) {
        if (dz >= 0.0) k = 2.0 / std::sqrt(2.0 * (1.0 + dz));
        else if (rho > 0.0) k = std::sqrt(2.0 * (1.0 - dz)) / rho;
        else return {0.0, 0.0, false};
    } else if (kind == STEREOGRAPHIC) {
        if (dz >= 0.0) k = 2.0 / (1.0 + dz);
        else if (rho > 0.0) k = 2.0 * (1.0 - dz) / (rho * rho);
        else return {0.0, 0.0, false};
    } else if (kind == ORTHOGRAPHIC) {
        if (!(dz >= 0.0)) return {0.0, 0.0, false};
        k = 1.0;
    } else {  // THOBY
        const double theta = std::atan2(rho, dz);
        if (!(THOBY_K2 * theta <= 0.5 * PI)) return {0.0, 0.0, false};
        k = rho > 0.0 ? THOBY_K1 * std::sin(THOBY_K2 * theta) / rho : THOBY_K1 * THOBY_K2;
    }
    return {dx * k, dy * k, true};
}

// Unit direction -> (longitude, height, ok) on the cylinder `kind` (lenslab.lenses.formulas.lonlat): false at
// the poles of the central cylinder and of Mercator, which lie at infinity.
inline P2 dir_to_lon_height(int64_t kind, double dx, double dy, double dz) {
    const double phi = std::atan2(dx, dz);
    const double c = std::hypot(dx, dz);
    if (kind == EQUIRECTANGULAR) return {phi, std::atan2(dy, c), true};
    if (kind == EQUAL_AREA_CYLINDRICAL) return {phi, dy, true};
    if (!(c > 0.0)) return {phi, 0.0, false};
    if (kind == CYLINDRICAL) return {phi, dy / c, true};
    return {phi, std::asinh(dy / c), true};  // MERCATOR
}

// P(r) = sum(c[i] r^i) by Horner's rule (lenslab.lenses.formulas.radial.Radial.scale)
inline double poly_scale(const double* c, int64_t n, double r) {
    double p = 0.0;
    for (int64_t j = n - 1; j >= 0; --j) p = p * r + c[j];
    return p;
}

// r_d / r_u of the FOV model: atan(r_u t2) / (omega r_u) with t2 = 2 tan(omega/2), and its limits
inline double fov_factor(double ru, double omega, double t2) {
    if (omega == 0.0) return 1.0;
    if (ru > 0.0) return std::atan(ru * t2) / (omega * ru);
    return t2 / omega;
}

// A unit ray (OpenCV's frame) -> (mx, my, ok) on the calibrated model's normalised plane
// (lenslab.lenses.formulas.calibrated.project; `q` as documented there).
inline P2 project_one(int64_t kind, double X, double Y, double Z, const double* q) {
    double mx, my;
    if (kind == PINHOLE || kind == FOV) {
        if (!(Z > 0.0)) return {0.0, 0.0, false};
        mx = X / Z;
        my = Y / Z;
        if (kind == FOV) {
            const double k = fov_factor(std::sqrt(mx * mx + my * my), q[0], q[1]);
            mx *= k;
            my *= k;
        }
    } else if (kind == EQUIDISTANT) {
        P2 p = dir_to_plane(EQUIDISTANT, X, Y, Z);
        if (!p.ok) return {0.0, 0.0, false};
        mx = p.x;
        my = p.y;
    } else if (kind == UNIFIED) {
        const double den = Z + q[0];
        if (!(Z > -q[1] && den > 0.0)) return {0.0, 0.0, false};
        mx = X / den;
        my = Y / den;
    } else if (kind == DOUBLE_SPHERE) {
        const double xi = q[0], al = q[1];
        const double d1 = std::sqrt(X * X + Y * Y + Z * Z);
        const double zz = xi * d1 + Z;
        const double d2 = std::sqrt(X * X + Y * Y + zz * zz);
        const double den = al * d2 + (1.0 - al) * zz;
        if (!(Z > -q[2] * d1 && den > 0.0)) return {0.0, 0.0, false};
        mx = X / den;
        my = Y / den;
    } else {  // EUCM
        const double al = q[0];
        const double dd = std::sqrt(q[1] * (X * X + Y * Y) + Z * Z);
        const double den = al * dd + (1.0 - al) * Z;
        if (!(Z > -q[2] * dd && den > 0.0)) return {0.0, 0.0, false};
        mx = X / den;
        my = Y / den;
    }
    return {mx, my, true};
}

// A plane point -> the unit ray (OpenCV's frame) of the calibrated model (calibrated.unproject).
inline P3 unproject_one(int64_t kind, double mx, double my, const double* q) {
    const double r2 = mx * mx + my * my;
    double X, Y, Z;
    if (kind == PINHOLE) {
        X = mx; Y = my; Z = 1.0;
    } else if (kind == FOV) {  // r_u = tan(r_d omega) / (2 tan(omega/2)), valid for r_d omega < pi/2
        const double rd = std::sqrt(r2);
        if (!(rd * q[0] < 0.5 * PI)) return {0.0, 0.0, 0.0, false};
        double k;
        if (q[0] == 0.0) k = 1.0;
        else if (rd > 0.0) k = std::tan(rd * q[0]) / (rd * q[1]);
        else k = q[0] / q[1];
        X = mx * k; Y = my * k; Z = 1.0;
    } else if (kind == EQUIDISTANT) {
        if (!(r2 < PI * PI)) return {0.0, 0.0, 0.0, false};  // the rim circle is the back pole
        const double s = std::sqrt(r2);  // azimuthal.plane_to_dir, equidistant
        const double k = s > 0.0 ? std::sin(s) / s : 1.0;
        X = mx * k; Y = my * k; Z = std::cos(s);
    } else if (kind == UNIFIED) {
        const double xi = q[0];
        const double disc = 1.0 + (1.0 - xi * xi) * r2;
        if (xi > 1.0 && !(disc > 0.0)) return {0.0, 0.0, 0.0, false};
        const double k = (xi + std::sqrt(std::fmax(disc, 0.0))) / (r2 + 1.0);
        X = k * mx; Y = k * my; Z = k - xi;
    } else if (kind == DOUBLE_SPHERE) {
        const double xi = q[0], al = q[1];
        const double qq = 1.0 - (2.0 * al - 1.0) * r2;
        if (al > 0.5 && qq < 0.0) return {0.0, 0.0, 0.0, false};
        const double mz = (1.0 - al * al * r2) / (al * std::sqrt(std::fmax(qq, 0.0)) + 1.0 - al);
        const double k = (mz * xi + std::sqrt(std::fmax(mz * mz + (1.0 - xi * xi) * r2, 0.0))) / (mz * mz + r2);
        X = k * mx; Y = k * my; Z = k * mz - xi;
        if (!(Z > -q[2])) return {0.0, 0.0, 0.0, false};  // the paper's region z > -w2 |x| (unit ray)
    } else {  // EUCM
        const double al = q[0], be = q[1];
        const double qq = 1.0 - (2.0 * al - 1.0) * be * r2;
        if (al > 0.5 && qq < 0.0) return {0.0, 0.0, 0.0, false};
        X = mx; Y = my;
        Z = (1.0 - be * al * al * r2) / (al * std::sqrt(std::fmax(qq, 0.0)) + 1.0 - al);
    }
    const double n = std::sqrt(X * X + Y * Y + Z * Z);
    if (!(n > 0.0 && n < INF)) return {0.0, 0.0, 0.0, false};
    X /= n; Y /= n; Z /= n;
    if (kind == EUCM && !(Z > -q[2] * std::sqrt(q[1] * (X * X + Y * Y) + Z * Z))) return {0.0, 0.0, 0.0, false};
    return {X, Y, Z, true};
}

}  // namespace lenslab::lens
