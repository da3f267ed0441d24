// The map lattice (lenslab.warp.lattice) and the separable samplers (lenslab.warp.filters): C++ kernels that
// give their NumPy references' bits (lenslab/warp/kernels/lattice_reference.py, reference.py). These files are
// built without fused multiply-adds (-ffp-contract=off, CMakeLists.txt), so every float64 step rounds as
// written, in the order written, exactly as NumPy and the references compute it.
#pragma once

#include <cstdint>

namespace lenslab {

// what a sample still needs after the lattice kernels (lenslab.warp.lattice.NEED_*)
constexpr int8_t NEED_DONE = 0, NEED_EXACT = 1, NEED_PROJECT = 2;

// Ghost nodes: fill invalid nodes of the (rows x cols) lattice next to valid ones, in place (an x pass, then
// a y pass; quadratic from three known neighbours in a line, linear from two). wrap > 0: x's period.
void ghost_pass(double* gx, double* gy, bool* have, int64_t rows, int64_t cols, double wrap);

// The Catmull-Rom interpolant of every cell of the node lattice (rows x cols, cells (rows-3) x (cols-3)) at
// the same fraction (tx, ty): ox, oy (rows-3, cols-3).
void lattice_grid(const double* nx, const double* ny, int64_t rows, int64_t cols, double tx, double ty, double wrap,
                  double* ox, double* oy);

// The bicubic coefficients of cell rows cb0..cb1: coef (cb1-cb0, ncx, K, 4, 4), c[b][a] of tx^a ty^b, for the
// cells with state 1 (components 0, 1) or 2 (components 2, 3, 4). nodes (K, ncy+3, ncx+3), state (ncy, ncx).
void cell_coefficients(const double* nodes, int64_t nk, const int8_t* state, int64_t ncy, int64_t ncx, int64_t cb0,
                       int64_t cb1, double wrap, double* coef);

struct LatticeBand {
    const double* coef;   // (rows, ncx, K, 4, 4) for cell rows cb0..
    int64_t nk;
    const int8_t* state;  // (ncy, ncx)
    int64_t ncy, ncx, cb0;
    const double* offs;   // (ho, wo, n, 2)
    int64_t ho, wo;
    int64_t h, w, n, r0;  // the band: rows r0..r0+h of width w, n samples per pixel
    float* xs;            // (h, w, n)
    float* ys;
    bool* valid;
    int8_t* need;
    double* dirs;         // (h, w, n, 3), written only for state-2 cells
};

// The map of a band from per-pixel offsets (lenslab.warp.lattice.lattice_eval); step: pixels per cell.
void lattice_eval(const LatticeBand& b, double step);
// The same for offsets shared by every pixel, walked cell by cell along each row (lattice_rows); inv = 1/step.
void lattice_rows(const LatticeBand& b, double inv);

// The lattice cells none of whose samples the source sees (lenslab.warp.lattice.outside_field): dirs (ny, nx, 3) the
// nodes' rays, have/seen (ny, nx); the field's m cones (axes (m, 3), angles (m,)); out (ny - 3, nx - 3)
void outside_field(const double* dirs, const bool* have, const bool* seen, int64_t ny, int64_t nx, const double* axes,
                   const double* angles, int64_t m, double bound, double slack, bool* out);
// Place n mapped samples at flat positions at[] of a band's maps: index coordinates xy - 0.5 rounded to float32
// where valid, 0 where not (lenslab.warp.lattice.place; xy (n, 2) float64).
void place(const int64_t* at, const double* xy, const bool* v, int64_t n, float* xs, float* ys, bool* valid);
// The footprints (n, 4 float32) thinner than min(sqrt(h2), longer side / sqrt(q2)): their indices into idx, how many
// (lenslab.warp.antialias.thicken_slivers; float32 steps as NumPy's).
int64_t thin_footprints(const float* foot, int64_t n, float h2, float q2, int64_t* idx);

// Fold tap (i, j) of a sample in piece p into that piece or across its edge into the neighbour
// (lenslab.warp.seam.fold_piece); table (pieces, 16).
void fold_piece(int64_t& i, int64_t& j, int64_t p, const int64_t* table);

struct Pieces {
    const int64_t* table;  // (np, 16); np == 0: no pieces
    int64_t np;
    const int64_t* grid;   // (gr, gc)
    int64_t gr, gc;
    int64_t cw, ch;
};

// The separable samplers (lenslab.warp.filters: kind 0 nearest, 1 tent, 2 Catmull-Rom, 3 Lanczos-3) over npix
// pixels of ns samples; src (sh, sw, nc) float32; out (npix, nc), alpha (npix,).
// One axis's 2 kind weights at position x (taps floor(x) - kind + 1 ..), each times the reciprocal of their sum
// (kind 1 tent, 2 Catmull-Rom, 3 Lanczos-3; separable.cpp).
void axis_weights(int kind, double x, double* w);
void separable(const float* src, int64_t sw, int64_t sh, int64_t nc, const float* xs, const float* ys,
               const bool* valid, int64_t npix, int64_t ns, bool wrap, bool top, bool bottom, const Pieces& pc,
               int kind, float* out, float* alpha);

}  // namespace lenslab
