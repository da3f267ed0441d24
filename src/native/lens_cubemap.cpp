// The cube map's direction -> pixel (lens_kernels.h), built with every multiply and add rounded as written
// (CMakeLists.txt), so it gives Cubemap._dir_to_pixel's bits (tests/lenses/test_native_cubemap_kernel.py).
#include <algorithm>
#include <cmath>

#include "lens_kernels.h"

namespace lenslab::lens {

// Cubemap._dir_to_pixel, one direction at a time, the same operations in the same order: the major axis of d (as
// given, not normalised; the first of x, y, z on ties), its face's cell and signed A and B axes, the position inside
// the face, kept BORDER_NUDGE px inside its right and bottom edges, then snap_to_image. Any NaN or infinite component
// makes NumPy's major component non-finite (argmax picks the first NaN, else an infinity), so the point is invalid.
void cubemap_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    const double w = p[0], h = p[1], ew = p[2], eh = p[3], slack = p[4], nudge = p[5];
    const double* faces = p + 6;  // per major axis +x, -x, +y, -y, +z, -z: col, row, sign of A, sign of B
    for (int64_t i = 0; i < n; ++i) {
        xy[2 * i] = 0.0;
        xy[2 * i + 1] = 0.0;
        ok[i] = false;
        const double dx = d[3 * i], dy = d[3 * i + 1], dz = d[3 * i + 2];
        if (!(std::isfinite(dx) && std::isfinite(dy) && std::isfinite(dz))) continue;
        const double ax = std::fabs(dx), ay = std::fabs(dy), az = std::fabs(dz);
        int axis;
        double t, m;
        if (ax >= ay && ax >= az) { axis = 0; t = ax; m = dx; }
        else if (ay >= az) { axis = 1; t = ay; m = dy; }
        else { axis = 2; t = az; m = dz; }
        if (!(t > 0.0)) continue;
        const double* f = faces + 4 * (2 * axis + (m < 0.0 ? 1 : 0));
        double uf = axis == 0 ? dz : dx;
        uf *= f[2];
        uf /= t;
        double vf = axis == 1 ? dz : dy;
        vf *= f[3];
        vf /= t;
        double x = uf + 1.0;
        x *= 0.5;
        x += f[0];
        x *= ew;
        double y = vf + 1.0;
        y *= 0.5;
        y += f[1];
        y *= eh;
        x = std::min(x, (f[0] + 1.0) * ew - nudge);
        y = std::min(y, (f[1] + 1.0) * eh - nudge);
        if (!(x >= -slack && x <= w + slack && y >= -slack && y <= h + slack)) continue;
        x = std::min(std::max(x, 0.0), w);
        y = std::min(std::max(y, 0.0), h);
        if (!std::isfinite(x * x + y * y)) continue;  // clean()'s test
        xy[2 * i] = x;
        xy[2 * i + 1] = y;
        ok[i] = true;
    }
}

}  // namespace lenslab::lens
