// The map lattice's field test (lenslab.warp.lattice.outside_field): the cells none of whose samples the source sees.
// The steps of its NumPy reference (lenslab.warp.kernels.lattice_reference.outside_field) in their order, per cell:
// the corners' rays summed and normalised, the cosine of the farthest corner, the bound's radius from its arc
// cosine; then each of the field's cones. A cone's test, acos(c . axis) - radius > angle, is the comparison
// c . axis < cos(angle + radius) wherever the two sides differ by more than 1e-12 (far more than the rounding of
// either), and the reference's arc cosine itself in the few cases between. Arc cosines, sines and cosines four cells at
// a time (glibc's vector maths where the build has it, NumPy's own loops in the reference: within a few ulps). Built
// without fused multiply-adds (CMakeLists.txt), as NumPy rounds.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "lattice.h"
#include "lens_vmath.h"

namespace lenslab {

namespace {
constexpr double PI = 3.14159265358979323846;
constexpr double SURE = 1e-12;  // the margin beyond which the cosine comparison decides a cone's test
inline double clip1(double v) { return std::min(std::max(v, -1.0), 1.0); }
}  // namespace

void outside_field(const double* dirs, const bool* have, const bool* seen, int64_t ny, int64_t nx, const double* axes,
                   const double* angles, int64_t m, double bound, double slack, bool* out) {
    using lens::vmath::acos4;
    const int64_t ncy = ny - 3, ncx = nx - 3, quad[4] = {nx + 1, nx + 2, 2 * nx + 1, 2 * nx + 2};
    std::vector<double> cos_a(static_cast<size_t>(m)), sin_a(static_cast<size_t>(m));  // each cone's, once
    for (int64_t a = 0; a < m; ++a) {
        cos_a[size_t(a)] = std::cos(angles[a]);
        sin_a[size_t(a)] = std::sin(angles[a]);
    }
    for (int64_t i = 0; i < ncy; ++i)
        for (int64_t j0 = 0; j0 < ncx; j0 += 4) {
            double c[3][4], cos_r[4] = {1.0, 1.0, 1.0, 1.0}, radius[4], sr[4], cr[4], dot[4], off[4];
            bool cand[4] = {false, false, false, false}, hit[4] = {false, false, false, false};
            for (int64_t l = 0; l < 4 && j0 + l < ncx; ++l) {
                const int64_t at = i * nx + j0 + l;
                bool ok = true;
                for (int64_t q : quad) ok = ok && have[at + q] && !seen[at + q];
                for (int k = 0; k < 3; ++k)
                    c[k][l] = ((dirs[3 * (at + quad[0]) + k] + dirs[3 * (at + quad[1]) + k]) + dirs[3 * (at + quad[2]) + k])
                              + dirs[3 * (at + quad[3]) + k];
                const double norm = std::sqrt((c[0][l] * c[0][l] + c[1][l] * c[1][l]) + c[2][l] * c[2][l]);
                cand[l] = ok && norm > 1.0;  // (four rays that nearly cancel have no bound)
                for (int k = 0; k < 3; ++k) c[k][l] /= cand[l] ? norm : 1.0;
                for (int64_t q : quad) {
                    const double* d = dirs + 3 * (at + q);
                    cos_r[l] = std::min(cos_r[l], (c[0][l] * d[0] + c[1][l] * d[1]) + c[2][l] * d[2]);
                }
                cos_r[l] = cand[l] ? clip1(cos_r[l]) : 1.0;
            }
            if (!(cand[0] || cand[1] || cand[2] || cand[3])) {
                for (int64_t l = 0; l < 4 && j0 + l < ncx; ++l) out[i * ncx + j0 + l] = false;
                continue;
            }
            acos4(radius, cos_r);
            for (int l = 0; l < 4; ++l) radius[l] = radius[l] * bound + slack;
            lens::vmath::sin_cos4(radius, sr, cr);
            for (int64_t a = 0; a < m; ++a) {
                const double ang = angles[a], ca = cos_a[size_t(a)], sa = sin_a[size_t(a)];
                bool exact = false, here[4] = {false, false, false, false};
                for (int l = 0; l < 4; ++l) {
                    dot[l] = 1.0;
                    if (!cand[l] || hit[l]) continue;
                    dot[l] = clip1((c[0][l] * axes[3 * a] + c[1][l] * axes[3 * a + 1]) + c[2][l] * axes[3 * a + 2]);
                    const double edge = ca * cr[l] - sa * sr[l];  // cos(angle + radius)
                    if (ang + radius[l] < PI - SURE && dot[l] < edge - SURE) hit[l] = true;
                    else if (!(ang + radius[l] < PI - SURE && dot[l] > edge + SURE)) exact = here[l] = true;
                }
                if (!exact) continue;
                acos4(off, dot);
                for (int l = 0; l < 4; ++l) hit[l] = hit[l] || (here[l] && off[l] - radius[l] > ang);
            }
            for (int64_t l = 0; l < 4 && j0 + l < ncx; ++l) out[i * ncx + j0 + l] = cand[l] && hit[l];
        }
}

}  // namespace lenslab
