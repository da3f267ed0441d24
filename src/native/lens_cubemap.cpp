// The cube maps' direction -> pixel (lens_kernels.h), built with every multiply and add rounded as written
// (CMakeLists.txt): the plain cube map gives Cubemap._dir_to_pixel's bits (tests/lenses/test_native_cubemap_kernel.py),
// the equi-angular one EquiAngularCubemap._dir_to_pixel's to a few ulps of its arc tangents
// (tests/lenses/test_native_eac_kernel.py).
#include <algorithm>
#include <cmath>

#include "lens_kernels.h"
#include "lens_vmath.h"

namespace lenslab::lens {

namespace {

// atan2(y[j], x[j]) of four pairs, written over y (glibc's vector maths four at a time: every element takes the
// same path whatever its place in a call, so a map does not depend on how the warp cut it into bands)
inline void atan2_4(double* y, const double* x) { vmath::atan2_4(y, y, x); }

// tan(a[j]) of four angles in [-pi/4, pi/4], written over a: sine over cosine
inline void tan_4(double* a) {
    double s[4], c[4];
    vmath::sin_cos4(a, s, c);
    for (int j = 0; j < 4; ++j) a[j] = s[j] / c[j];
}

// snap_to_image (within `slack` px of the edges counts, moved onto them) and clean()'s finite test, then the store
inline void store(int64_t i, double x, double y, double w, double h, double slack, double* xy, bool* ok) {
    if (!(x >= -slack && x <= w + slack && y >= -slack && y <= h + slack)) return;
    x = std::min(std::max(x, 0.0), w);
    y = std::min(std::max(y, 0.0), h);
    if (!std::isfinite(x * x + y * y)) return;
    xy[2 * i] = x;
    xy[2 * i + 1] = y;
    ok[i] = true;
}

}  // namespace

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
        store(i, x, y, w, h, slack, xy, ok);
    }
}


// EquiAngularCubemap._dir_to_pixel, four directions at a time: the major axis of d (the first of x, y, z on ties), its
// face's slot and signed A and B components, the angles atan(d.A / t) and atan(d.B / t) (as atan2(d.A, t): t > 0, and
// no rounding of the quotient), the face fractions (4/pi) angle, the nudge off the face's right and bottom edges, the
// position in the 3x2 layout with its pad, then snap_to_image. Non-finite components make the point invalid.
void eac_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    const double w = p[0], h = p[1], pu = p[2], pv = p[3], slack = p[4], fx_max = p[5], fy_max = p[6];
    const double* faces = p + 7;  // per major axis +x, -x, +y, -y, +z, -z: col, row, index and sign of A, of B
    const double four_over_pi = 4.0 / M_PI;
    for (int64_t i0 = 0; i0 < n; i0 += 4) {
        const int64_t m = std::min<int64_t>(4, n - i0);
        double au[4] = {0.0, 0.0, 0.0, 0.0}, av[4] = {0.0, 0.0, 0.0, 0.0}, t[4] = {1.0, 1.0, 1.0, 1.0};
        const double* face[4] = {faces, faces, faces, faces};
        bool good[4] = {false, false, false, false};
        for (int64_t j = 0; j < m; ++j) {
            const int64_t i = i0 + j;
            xy[2 * i] = 0.0;
            xy[2 * i + 1] = 0.0;
            ok[i] = false;
            const double* v = d + 3 * i;
            if (!(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]))) continue;
            const double ax = std::fabs(v[0]), ay = std::fabs(v[1]), az = std::fabs(v[2]);
            int axis;
            if (ax >= ay && ax >= az) axis = 0;
            else if (ay >= az) axis = 1;
            else axis = 2;
            const double tj = axis == 0 ? ax : axis == 1 ? ay : az;
            if (!(tj > 0.0)) continue;
            const double* f = faces + 6 * (2 * axis + (v[axis] < 0.0 ? 1 : 0));
            au[j] = v[int(f[2])] * f[3];
            av[j] = v[int(f[4])] * f[5];
            t[j] = tj;
            face[j] = f;
            good[j] = true;
        }
        atan2_4(au, t);
        atan2_4(av, t);
        for (int64_t j = 0; j < m; ++j) {
            if (!good[j]) continue;
            const int64_t i = i0 + j;
            const double* f = face[j];
            double fx = four_over_pi * au[j];
            fx += 1.0;
            fx *= 0.5;
            double fy = four_over_pi * av[j];
            fy += 1.0;
            fy *= 0.5;
            fx = std::min(fx, fx_max);
            fy = std::min(fy, fy_max);
            store(i, w * (pu + (f[0] + fx) * (1.0 - 2.0 * pu) / 3.0), h * (pv + 0.5 * f[1] + fy * (0.5 - 2.0 * pv)), w,
                  h, slack, xy, ok);
        }
    }
}

// EquiAngularCubemap._pixel_to_dir, four pixels at a time: the face column and row and the fractions across them (with
// the pad), the tests of the fractions and of the image, the cube coordinates tan(pi/4 (2 f - 1)) (sine over cosine),
// d = uf A + vf B + C with the face's axes, normalised; clean()'s finite test.
void eac_dirs(const double* xy, int64_t n, const double* p, double* d, bool* ok) {
    const double w = p[0], h = p[1], pu = p[2], pv = p[3], kx = p[4], ky = p[5];
    const double* axes = p + 6;  // per slot (row by row): A, B, C
    const double quarter = M_PI / 4;
    for (int64_t i0 = 0; i0 < n; i0 += 4) {
        const int64_t m = std::min<int64_t>(4, n - i0);
        double a[4] = {0.0, 0.0, 0.0, 0.0}, b[4] = {0.0, 0.0, 0.0, 0.0};
        int slot[4] = {0, 0, 0, 0};
        bool good[4] = {false, false, false, false};
        for (int64_t j = 0; j < m; ++j) {
            const double x = xy[2 * (i0 + j)], y = xy[2 * (i0 + j) + 1];
            double t = x / w;
            t -= pu;
            t *= kx;
            const double col = std::min(std::max(std::floor(t), 0.0), 2.0);
            const double fx = t - col;
            const double yn = y / h;
            const double row = std::min(std::max(std::floor(2.0 * yn), 0.0), 1.0);
            const double fy = (yn - pv - 0.5 * row) / ky;
            good[j] = t >= 0.0 && t <= 3.0 && fy >= 0.0 && fy <= 1.0 && x >= 0.0 && x <= w && y >= 0.0 && y <= h
                      && std::isfinite(t) && std::isfinite(yn);
            if (!good[j]) continue;
            slot[j] = int(row) * 3 + int(col);
            a[j] = quarter * (2.0 * fx - 1.0);
            b[j] = quarter * (2.0 * fy - 1.0);
        }
        tan_4(a);
        tan_4(b);
        for (int64_t j = 0; j < m; ++j) {
            double* o = d + 3 * (i0 + j);
            o[0] = o[1] = o[2] = 0.0;
            ok[i0 + j] = false;
            if (!good[j]) continue;
            const double uf = a[j], vf = b[j];
            const double* A = axes + 9 * slot[j];
            const double norm = std::sqrt(uf * uf + vf * vf + 1.0);
            double v[3];
            for (int k = 0; k < 3; ++k) {
                v[k] = uf * A[k] + vf * A[3 + k] + A[6 + k];
                v[k] /= norm;
            }
            if (!std::isfinite(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])) continue;
            o[0] = v[0];
            o[1] = v[1];
            o[2] = v[2];
            ok[i0 + j] = true;
        }
    }
}

}  // namespace lenslab::lens
