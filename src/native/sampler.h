#pragma once
#include <cstdint>
#include "kernels.h"

namespace lenslab {

constexpr uint32_t TAP_INVALID = 0xFFFFFFFFu;  // no source: colour and alpha 0
constexpr uint32_t TAP_FOLDED = 0xFFFFFFFEu;   // taps across an edge: the folding sampler

// what bilinear1 says of the values it wrote (alpha is 0 or 1, always in range)
constexpr int SAMPLED_NON_FINITE = 1;  // some value is NaN or infinite
constexpr int SAMPLED_COVERED = 2;     // some sample is valid (alpha 1)
// n pixels, one sample each: out (n, nc), alpha (n,); returns SAMPLED_* flags. zeroed: out and alpha hold +0 already
// (fresh zeroed memory), so the samples without a source are not written (their pages are not touched)
int bilinear1(const float* flat, int64_t sw, int64_t sh, int64_t nc, const float* xs, const float* ys,
               const bool* valid, int64_t n, Border b, float* out, float* alpha, bool zeroed = false);
// npix pixels of ns samples each (xs (npix, ns)); nc <= 64
void bilinear_n(const float* flat, int64_t sw, int64_t sh, int64_t nc, const float* xs, const float* ys,
                const bool* valid, int64_t npix, int64_t ns, Border b, float* out, float* alpha);
void taps_of(int64_t sw, int64_t sh, const float* xs, const float* ys, const bool* valid, int64_t n,
             uint32_t* off, float* tx, float* ty);
void from_taps(const float* flat, int64_t sw, int64_t nc, const uint32_t* off, const float* tx, const float* ty,
               int64_t n, float* out, float* alpha);
void folded(const float* flat, int64_t sw, int64_t sh, int64_t nc, const int64_t* idx, const float* xs,
            const float* ys, int64_t m, Border b, float* out, float* alpha);
// The source pixels a band's taps read (from_taps: off, n pixels; folded: xs, ys, m positions), all four of each
// pixel's taps, marked 1 in `read` (sh x sw, kept across bands)
void tap_reads(int64_t sw, int64_t sh, const uint32_t* off, int64_t n, const float* xs, const float* ys, int64_t m,
               Border b, uint8_t* read);
// Each row's marked columns of `read` (sh x sw) within two spans [s0, s1) and [s2, s3) (spans: sh x 4; all 0 for a
// row not read): the first marked column to the last, less the longest unread run between them (a row read on both
// sides of the seam leaves out the columns between); the second span is empty (0, 0) where none is left out
void read_spans(int64_t sw, int64_t sh, const uint8_t* read, int64_t* spans);

// The footprint prefilter (lenslab.warp.pyramid): npix pixels of ns samples; foot (npix, ns, 4);
// shapes (nlev, 2) (height, width); offsets (nlev,) into rest for levels >= 1; row_len samples (a multiple of ns)
// make one output row, whose footprints may share windows (footprint_chunks.h).
void footprint(const float* level0, const float* rest, const int64_t* shapes, const int64_t* offsets, int64_t nlev,
               int64_t nc, const float* xs, const float* ys, const bool* valid, const float* foot, int64_t npix,
               int64_t ns, int64_t row_len, Border b, double max_taps, float* out, float* alpha);

// Footprint sides of rows top..top+h of a one-sample map (xs, ys, vs: nrows x w): foot (h, w, 4) = a, b; edge
// (h, w): a neighbour's validity differs. piece (nrows x w, or null for one piece): each pixel's piece number; a
// neighbour in another piece does not count. coarse (h * w, or null): the flat indices (into h x w) of the valid
// pixels with a side that may be longer than `far` texels, in order; returns their count.
int64_t neighbour_secants(const float* xs, const float* ys, const bool* vs, int64_t nrows, int64_t w, int64_t top,
                          int64_t h, double wrap, const int32_t* piece, float* foot, bool* edge, double far,
                          int64_t* coarse);

}  // namespace lenslab
