// The steps every whole-image direction -> pixel kernel shares (lens_tile_pixels.cpp, lens_pixels.cpp): Lens.dir_to_pixel's
// normalisation, Lens.uv_to_pixel with Lens.snap_to_image, and the cleared output of an unseen direction, each the
// same operations in the same order as the NumPy methods.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace lenslab::lens {

inline void clear2(int64_t i, double* out, bool* ok) {
    out[2 * i] = 0.0;
    out[2 * i + 1] = 0.0;
    ok[i] = false;
}

// direction i scaled to unit length as Lens.dir_to_pixel does; false for zero and non-finite ones
inline bool unit_dir(const double* d, int64_t i, double& x, double& y, double& z) {
    x = d[3 * i];
    y = d[3 * i + 1];
    z = d[3 * i + 2];
    const double n2 = x * x + y * y + z * z;
    if (!(n2 > 0.0 && std::isfinite(n2))) return false;
    const double s = std::sqrt(n2);
    x /= s;
    y /= s;
    z /= s;
    return true;
}

// direction i's (u, v) on a pinhole's plane (Lens.dir_to_pixel's normalisation, then Perspective.dir_to_uv: x / z and
// y / z over t and t_v); false for zero and non-finite directions and those not in front (z <= 0)
inline bool pinhole_uv(const double* d, int64_t i, double t, double tv, double& u, double& v) {
    double x, y, z;
    if (!unit_dir(d, i, x, y, z) || !(z > 0.0)) return false;
    const double inv = 1.0 / z;
    u = x * inv;
    v = y * inv;
    u /= t;
    v /= tv;
    return true;
}

// Lens.uv_to_pixel then Lens.snap_to_image (W, H, H / W, slack), writing pixel i when it is inside
inline void uv_pixel(int64_t i, double u, double v, double w, double h, double aspect, double slack, double* xy,
                     bool* ok) {
    double x = u + 1.0;
    x *= 0.5 * w;
    double y = w != h ? 1.0 - v / aspect : 1.0 - v;
    y *= 0.5 * h;
    if (x >= -slack && x <= w + slack && y >= -slack && y <= h + slack) {
        xy[2 * i] = std::min(std::max(x, 0.0), w);
        xy[2 * i + 1] = std::min(std::max(y, 0.0), h);
        ok[i] = true;
    }
}

}  // namespace lenslab::lens
