// The steps the calibrated models' kernels share (lens_calibrated.cpp, lens_solved.cpp): the image test with its
// slack, a direction as a unit ray in OpenCV's frame, and OpenCV's distortion of the normalised plane with its
// Jacobian. Internal linkage (an unnamed namespace), as they had in the one file they came from: each kernel inlines
// them and compiles to the same instructions.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "lens_kernels.h"

namespace lenslab::lens {

namespace {

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

}  // namespace

}  // namespace lenslab::lens
