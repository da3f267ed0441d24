// The lens models' array kernels (lens_tile_pixels.cpp, lens_pixels.cpp, lens_cubemap.cpp, lens_dirs.cpp,
// lens_calibrated.cpp, lens_solved.cpp): direction -> pixel of the models that have one compiled,
// and the numerically inverted sides of the distortion and calibrated models. Each loops over n elements with
// no temporaries; `ok` outputs are false (and the positions 0) where the model does not see an element.
// NumPy references: lenslab/lenses/formulas/reference.py.
#pragma once

#include <cstdint>

#include "lens_solve.h"

namespace lenslab::lens {

struct Table { const double* v; int64_t len; double step; };

// OpenCV's distortion of the normalised plane: rational radial factor, tangential p1 p2, thin prism s[4]
struct Distortion { const double* a; const double* b; double p1, p2; const double* s; bool tangential; double fold; };

struct Intrinsics { double fx, fy, skew, cx, cy; };
struct Frame { double width, height, slack; };

// equirect: p = W, H, lon_min, lon_max, lat_min, lat_max (radians), full sphere, wraps, edge slack
void equirect_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok);

// The whole-image models' dir -> pixel (Lens.dir_to_pixel: normalise, dir_to_uv, uv_to_pixel, snap_to_image),
// the same operations in the same order as their NumPy methods.
// perspective: p = W, H, t, t_v, H / W, edge slack
void perspective_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok);
// hammer: p = W, H, H / W, edge slack
void hammer_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok);

// pixel -> unit direction (DirKernels, lens_dirs.cpp) of a fisheye: p = W, H, H / W, mapping code, plane scale, the
// largest squared radius, cx, cy, r_ref, off-centre; of a fisheye turned in the camera: those, then M (9, row-major:
// the camera sees d M); of a cylinder: p = W, H, H / W, cylinder code, F, Fv, the equal-area height limit
void fisheye_dirs(const double* xy, int64_t n, const double* p, double* d, bool* ok);
void turned_fisheye_dirs(const double* xy, int64_t n, const double* p, double* d, bool* ok);
void cylinder_dirs(const double* xy, int64_t n, const double* p, double* d, bool* ok);
// of an equirect: p = W, H, whole sphere (0 or 1), lon0, lon1, lat0, lat1 (radians), pole at the top, at the bottom
void equirect_dirs(const double* xy, int64_t n, const double* p, double* d, bool* ok);
// of Pannini: p = W, H, H / W, d, x_f, (d + 1)^2, 1 - d^2, the largest |longitude| (with its slack), 1 - vcomp
void pannini_dirs(const double* xy, int64_t n, const double* p, double* d, bool* ok);

// fisheye (lens_pixels.cpp): p = W, H, H / W, mapping code, plane scale, largest s over it (with the rim slack),
// off-centre (0 or 1), cx, cy, r_ref, edge slack, turned (0 or 1), then the turn R (9, row-major: the lens sees R d)
void fisheye_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok);
// two fisheyes back to back (lens_pixels.cpp): p = W, H, half width, mapping code, plane scale, largest s over it (with
// the rim slack), the front lens's left edge, edge slack, half / H, the largest x of the left half
void dual_fisheye_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok);
// sinusoidal (lens_pixels.cpp): p = W, H, H / W, edge slack
void sinusoidal_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok);
// Pannini (lens_pixels.cpp): p = W, H, H / W, d, x_f, cos of the edge longitude, 1 - vcomp, edge slack
void pannini_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok);
// swirl of a pinhole (lens_pixels.cpp): p = W, H, H / W, t, t_v, -amount, edge slack
void swirl_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok);
// cylinders (lens_pixels.cpp): p = W, H, H / W, cylinder code, F, Fv, largest |longitude| (with its slack), edge slack
void cylinder_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok);
// Brown distortion of a pinhole (lens_pixels.cpp): p = W, H, H / W, t, t_v, k1, k2, fold radius squared, edge slack
void brown_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok);

// cube map (Cubemap._dir_to_pixel: d as given, not normalised): p = W, H, face width, face height, edge slack,
// border nudge, then per major axis +x, -x, +y, -y, +z, -z: the face's column, row, sign of A, sign of B
void cubemap_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok);
// equi-angular cube map (EquiAngularCubemap._dir_to_pixel, v360's eac layout): p = W, H, pad / W, pad / H, edge
// slack, the largest face fractions across and down (the border nudge), then per major axis +x, -x, +y, -y, +z, -z:
// the face's column, row, the component of d along A and its sign, the component along B and its sign
void eac_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok);
// and its pixel -> unit direction (EquiAngularCubemap._pixel_to_dir; a DirKernel): p = W, H, pad / W, pad / H,
// 3 / (1 - 2 pad / W), 1/2 - 2 pad / H, then per slot (row by row) its axes A, B, C (9)
void eac_dirs(const double* xy, int64_t n, const double* p, double* d, bool* ok);

// a tiled grid: each direction to the first tile that sees it (Tiled.dir_to_pixel). p = the number of tiles, then
// per tile: its kernel's number in pixel_kernel_ids(), the count of its parameters, the cosine of its reach (-1:
// no cone test), its axis (3), its turn R (9, row-major: the tile sees d R), its offset (2) and the largest
// position inside it (2), then its kernel's parameters
void tiled_pixels(const double* d, int64_t n, const double* p, double* xy, bool* ok);

using PixelFn = void (*)(const double*, int64_t, const double*, double*, bool*);
// the whole-image kernels a tile may have, by number (0 equirect, 1 perspective, 2 hammer); nullptr beyond
PixelFn pixel_fn(int64_t id);

void division_unbend(const double* uv, int64_t n, double k1, double k2, double hi, double f_hi, bool strict, bool pole,
                     const Table& table, const Solver& s, double* out, bool* ok);
void brown_bend(const double* uv, int64_t n, double k1, double k2, double hi, double rd_fold, const Table& table,
                const Solver& s, double* out, bool* ok);
void tan_fisheye_dir_to_uv(const double* d, int64_t n, double F, double hi, double psi_max, bool strict,
                           const Table& table, const Solver& s, double* out, bool* ok);

void distort_points(const double* x, const double* y, int64_t n, const Distortion& dist, double* xd, double* yd,
                    bool* ok);
void calibrated_project(const double* d, int64_t n, int64_t kind, const double* q, const Distortion* dist,
                        const Intrinsics& k, const Frame& frame, double* xy, bool* ok);
int64_t calibrated_unproject(const double* xy, int64_t n, int64_t kind, const double* q, const Distortion* dist,
                             double hi, double f_hi, bool strict, const Table& table, const Solver& s, double tol_2d,
                             int64_t max_iter_2d, const Intrinsics& k, double* d, bool* ok);
int64_t ocam_project(const double* d, int64_t n, const double* pol_unit, int64_t npol, double hi, double a_hi,
                     bool strict, const Table& table, const Solver& s, double c, double dd, double e, double xc,
                     double yc, const Frame& frame, double* xy, bool* ok);

void lensfun_dir_to_pixel(const double* d, int64_t n, int64_t kind, double f, const double* coeffs, int64_t ncoeffs,
                          double r_lim, double cx, double cy, double norm, double* xy, bool* ok);

}  // namespace lenslab::lens
