// The closed-form sides of the calibrated models (lens_kernels.h): OpenCV's distortion of points of the normalised
// plane, the calibrated projections with their distortion, intrinsics and image test (OpenCV, Kannala-Brandt,
// omnidir, double sphere, EUCM, FOV), and the lensfun profiles' direction -> pixel (the projection, then the radial
// polynomial), built with every multiply and add rounded as written (CMakeLists.txt). Their solved inverses are in
// lens_solved.cpp. NumPy references: lenslab/lenses/formulas/reference.py (tests/lenses/test_native_lens_kernels.py).
#include "lens_calibrated_steps.h"
#include "lens_kernels.h"
#include "lens_pixel_steps.h"

#include <cmath>

namespace lenslab::lens {

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
