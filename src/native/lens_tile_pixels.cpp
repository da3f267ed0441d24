// Direction -> pixel of the equirect, perspective and Hammer models (their PixelKernel, lens_kernels.h) and of tiled
// grids of them (a tile runs one of those three: pixel_fn), the steps of the models' NumPy dir_to_pixel in their
// order, built with every multiply and add rounded as written (CMakeLists.txt). The equirect's arc tangents and
// hypotenuses come from glibc's vector maths four at a time where it has them. Held to the models' NumPy steps by
// tests/lenses/test_native_lens_kernels.py.
#include "lens_kernels.h"
#include "lens_pixel_steps.h"

#include <algorithm>
#include <cmath>

#ifdef LENSLAB_MVEC  // glibc's vector maths (libmvec, glibc 2.35 or later; CMakeLists.txt finds it)
#include <immintrin.h>
extern "C" __m256d _ZGVdN4vv_atan2(__m256d, __m256d);
extern "C" __m256d _ZGVdN4vv_hypot(__m256d, __m256d);
#endif

namespace lenslab::lens {

void perspective_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    const double w = p[0], h = p[1], t = p[2], tv = p[3], aspect = p[4], slack = p[5];
    for (int64_t i = 0; i < n; ++i) {
        clear2(i, xy, ok);
        double u, v;
        if (pinhole_uv(d, i, t, tv, u, v)) uv_pixel(i, u, v, w, h, aspect, slack, xy, ok);
    }
}

void hammer_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    const double w = p[0], h = p[1], aspect = p[2], slack = p[3];
    for (int64_t i = 0; i < n; ++i) {
        clear2(i, xy, ok);
        double dx, dy, dz;
        if (!unit_dir(d, i, dx, dy, dz)) continue;
        const double c = std::hypot(dx, dz);
        const double a = std::fabs(dz) + c;
        double hh = 0.0;
        if (a > 0.0) {
            hh = c / a;
            hh *= 0.5;
            hh = std::sqrt(hh);
        }
        const double big = a * hh, small = std::fabs(dx) * hh;
        const bool front = dz >= 0.0;
        const double cc = front ? big : small;
        const double cs = std::copysign(front ? small : big, dx);
        const double z = std::sqrt(cc + 1.0);
        uv_pixel(i, cs / z, dy / (z * 2.0), w, h, aspect, slack, xy, ok);
    }
}

// The longitude atan2(dx, dz), cos(latitude) hypot(dx, dz) and latitude atan2(dy, hypot) of `m` <= 4 unit directions
// (x, y, z in a[0..3], a[4..7], a[8..11]; written over them). With glibc's vector maths (libmvec) four at a time; every
// element takes the same path whatever its place in a call (a short block is padded), so a map's values do not
// depend on how the warp cut it into bands.
inline void lon_lat4(double* a) {
#ifdef LENSLAB_MVEC
    const __m256d x = _mm256_loadu_pd(a), y = _mm256_loadu_pd(a + 4), z = _mm256_loadu_pd(a + 8);
    const __m256d c = _ZGVdN4vv_hypot(x, z);
    _mm256_storeu_pd(a, _ZGVdN4vv_atan2(x, z));
    _mm256_storeu_pd(a + 4, _ZGVdN4vv_atan2(y, c));
#else
    for (int j = 0; j < 4; ++j) {
        const double x = a[j], y = a[4 + j], z = a[8 + j];
        a[j] = std::atan2(x, z);
        a[4 + j] = std::atan2(y, std::hypot(x, z));
    }
#endif
}

void equirect_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    const double w = p[0], h = p[1], lon0 = p[2], lon1 = p[3], lat0 = p[4], lat1 = p[5], e = p[8];
    const bool full = p[6] != 0.0, wraps = p[7] != 0.0;
    for (int64_t i0 = 0; i0 < n; i0 += 4) {
        const int64_t m = std::min<int64_t>(4, n - i0);
        double a[12] = {0.0};
        bool good[4] = {false, false, false, false};
        for (int64_t j = 0; j < m; ++j) {
            const int64_t i = i0 + j;
            clear2(i, xy, ok);
            double dx = d[3 * i], dy = d[3 * i + 1], dz = d[3 * i + 2];
            const double n2 = dx * dx + dy * dy + dz * dz;
            if (!(n2 > 0.0 && std::isfinite(n2))) continue;
            const double sn = std::sqrt(n2);
            a[j] = dx / sn;
            a[4 + j] = dy / sn;
            a[8 + j] = dz / sn;
            good[j] = true;
        }
        if (!(good[0] || good[1] || good[2] || good[3])) continue;  // nothing seen: no trigonometry
        lon_lat4(a);
        for (int64_t j = 0; j < m; ++j) {
            if (!good[j]) continue;
            const int64_t i = i0 + j;
            double phi = a[j];
            const double theta = a[4 + j];
            double x, y;
            if (full) {
                x = phi / PI;
                x += 1.0;
                x *= 0.5 * w;
                y = theta / (PI / 2);
                y = 1.0 - y;
                y *= 0.5 * h;
            } else {
                if (!wraps && phi < lon0) phi += 2 * PI;
                x = (phi - lon0) / (lon1 - lon0) * w;
                y = (lat1 - theta) / (lat1 - lat0) * h;
                if (!(x >= -e && x <= w + e && y >= -e && y <= h + e)) continue;
                x = std::min(std::max(x, 0.0), w);
                y = std::min(std::max(y, 0.0), h);
            }
            if (std::isfinite(x) && std::isfinite(y)) {
                xy[2 * i] = x;
                xy[2 * i + 1] = y;
                ok[i] = true;
            }
        }
    }
}

PixelFn pixel_fn(int64_t id) {
    switch (id) {
        case 0: return equirect_pixels;
        case 1: return perspective_pixels;
        case 2: return hammer_pixels;
        default: return nullptr;
    }
}

void tiled_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok) {
    constexpr int64_t B = 256;  // directions per block: the block's buffers stay in the L1 cache
    const int64_t ntiles = int64_t(p[0]);
    double u[3 * B], buf[3 * B], lxy[2 * B];
    bool free_[B], lok[B];
    int64_t idx[B];
    for (int64_t b0 = 0; b0 < n; b0 += B) {
        const int64_t m = std::min(B, n - b0);
        for (int64_t j = 0; j < m; ++j) {
            clear2(b0 + j, xy, ok);
            free_[j] = unit_dir(d + 3 * b0, j, u[3 * j], u[3 * j + 1], u[3 * j + 2]);
        }
        const double* t = p + 1;
        for (int64_t k = 0; k < ntiles; ++k) {
            const PixelFn fn = pixel_fn(int64_t(t[0]));
            const int64_t np_ = int64_t(t[1]);
            const double reach = t[2];
            const double* axis = t + 3;
            const double* R = t + 6;
            const double ox = t[15], oy = t[16], limx = t[17], limy = t[18];
            int64_t c = 0;
            for (int64_t j = 0; j < m; ++j) {
                if (!free_[j]) continue;
                const double* v = u + 3 * j;
                if (reach > -1.0 && !(axis[0] * v[0] + axis[1] * v[1] + axis[2] * v[2] >= reach)) continue;
                for (int q = 0; q < 3; ++q) buf[3 * c + q] = v[0] * R[q] + v[1] * R[3 + q] + v[2] * R[6 + q];
                idx[c++] = j;
            }
            if (c && fn) {
                fn(buf, c, t + 19, lxy, lok);
                for (int64_t e = 0; e < c; ++e) {
                    if (!lok[e]) continue;
                    const int64_t i = b0 + idx[e];
                    xy[2 * i] = std::min(lxy[2 * e], limx) + ox;  // off the tile's right and bottom edges
                    xy[2 * i + 1] = std::min(lxy[2 * e + 1], limy) + oy;
                    ok[i] = true;
                    free_[idx[e]] = false;
                }
            }
            t += 19 + np_;
        }
    }
}

}  // namespace lenslab::lens
