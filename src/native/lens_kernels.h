// The lens models' array kernels (lens_kernels.cpp): direction -> pixel of the models that have one compiled,
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
