// The footprint prefilter: each output sample averages the bilinear source over its footprint, a
// parallelogram read from the finest pyramid level at which it spans at most max_taps texels (see
// lenslab/warp/antialias.py for the method). By Green's theorem, edge by edge: the integral over y of F at the
// right ends of the parallelogram's rows less F at the left ends, F the integral of the row's linear interpolant
// from the window's first texel (per-row prefix sums of the window: O(1) per point, whatever the width), each
// edge cut at the texel rows and integrated by 2-point Gauss-Legendre. In float64, in the order of the NumPy
// reference (lenslab.warp.kernels.reference.prefix_slices); a footprint clipped by its window (beyond the
// coarsest level) takes the texel weights of the slices instead (reference.slice_weights). The edge integrals
// are in footprint_edges.h. The footprints of a run of pixels in an output row share one window
// (footprint_chunks.h), and neighbouring pixels of a row share the side between them: a quadrilateral whose
// shared side is integrated once for both (reference.footprint with rows of pixels).
// This file holds the runs: the footprints of each chunk of a row set up (footprint_setup.h) and their texels
// prefetched, the chunk's shared windows loaded and integrated (footprint_chunks.h, footprint_edges.h; a footprint
// its window clips, footprint_weights.h), and each pixel's samples summed; and the filter's binding. (The binding
// stays in this file: the entry below is inlined into it, so each channel count's loop is called from two places
// and the compiler builds it to the instructions measured in docs/design.md; with the binding in a file of its own
// it built them otherwise.)
#include <algorithm>
#include <climits>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include "bind.h"
#include "footprint_chunks.h"
#include "footprint_edges.h"
#include "footprint_setup.h"
#include "footprint_weights.h"
#include "sampler.h"

namespace lenslab {
namespace {

using namespace footprint_edges;

// NC > 0: that many channels, known to the compiler; NC == 0: nc (<= 64) at run time. The samples are read in
// chunks of CHUNK consecutive samples of one row of row_len (a multiple of ns); the footprints of a chunk at one
// level and slicing direction share windows (footprint_chunks.h), so a sample's value depends on its row alone,
// not on how the rows are split into bands.
template <int NC>
void footprint_t(const float* __restrict__ level0, const float* __restrict__ rest, const int64_t* shapes,
                 const int64_t* offsets, int64_t nlev, int64_t nc_, const float* __restrict__ xs,
                 const float* __restrict__ ys, const bool* __restrict__ valid, const float* __restrict__ foot,
                 int64_t npix, int64_t ns, int64_t row_len, Border b, double max_taps, float* __restrict__ out,
                 float* __restrict__ alpha) {
    typedef typename Lanes<NC>::type L;
    const int64_t nc = NC > 0 ? NC : nc_;
    const double inv = 1.0 / double(ns);
    const double h0 = double(shapes[0]);
    double wgt[(WINDOW + 2) * STRIDE];
    std::vector<Ragged<NC>> shared_buf(1);  // (the shared window's rows: on the heap)
    Ragged<NC>& G = shared_buf[0];
    RowPtrs<NC> R;
    Item items_buf[2][CHUNK];
    int cur = 0;
    int64_t next_c = -1;
    // the footprints of the chunk at c (in a row ending at end), their windows' texels prefetched
    // rows of pixels (one sample each): neighbours share sides
    const bool share = ns == 1 && row_len > 1;
    auto one = [&](int64_t s, Item& it) {
        if (!valid[s]) it.mode = 0;
        else setup(it, shapes, nlev, h0, xs[s], ys[s], foot + 4 * s, max_taps);
    };
    auto prepare = [&](int64_t c, int64_t end, Item* its) {
        const int n = int(std::min<int64_t>(CHUNK, end - c));
        for (int k = 0; k < n; ++k) one(c + k, its[k]);
        if (share) {  // the sides shared with the neighbours, the one before and the one after the chunk included
            const int64_t row0 = c - (c % row_len);
            Item before, after;
            before.mode = after.mode = 0;
            if (c > row0) one(c - 1, before);
            if (c + n < row0 + row_len) one(c + n, after);
            link(before, its[0], shapes, b.wrap);
            for (int k = 0; k + 1 < n; ++k) link(its[k], its[k + 1], shapes, b.wrap);
            link(its[n - 1], after, shapes, b.wrap);
            for (int k = 0; k < n; ++k) finish_quad(its[k]);
        }
        // the texels of the level-0 windows' bounding box, a cache line at a time (any other: window by window)
        const int64_t lh0 = shapes[0], lw0 = shapes[1];
        int64_t x0 = INT64_MAX, x1 = INT64_MIN, y0 = INT64_MAX, y1 = INT64_MIN;
        for (int k = 0; k < n; ++k) {
            const Item& it = its[k];
            if (it.mode != 1) continue;
            if (it.lev == 0) {
                x0 = std::min(x0, it.wx0); x1 = std::max(x1, it.wx0 + it.nwx);
                y0 = std::min(y0, it.wy0); y1 = std::max(y1, it.wy0 + it.nwy);
                continue;
            }
            const int64_t lh = shapes[2 * it.lev], lw = shapes[2 * it.lev + 1];
            const float* lbuf = rest + offsets[it.lev];
            const int64_t a = std::max<int64_t>(0, std::min(lw - 1, it.wx0));
            const int64_t e = std::max<int64_t>(0, std::min(lw - 1, it.wx0 + it.nwx - 1));
            for (int64_t y = std::max<int64_t>(0, it.wy0); y < std::min(lh, it.wy0 + it.nwy); ++y) {
                __builtin_prefetch(lbuf + (y * lw + a) * nc);
                __builtin_prefetch(lbuf + (y * lw + e) * nc + nc - 1);
            }
        }
        if (x0 < x1) {
            x0 = std::max<int64_t>(0, x0); x1 = std::min(lw0, x1);
            y0 = std::max<int64_t>(0, y0); y1 = std::min(lh0, y1);
            if (x0 < x1 && y0 < y1 && (x1 - x0) * (y1 - y0) <= CAP)
                for (int64_t y = y0; y < y1; ++y) {
                    const float* r = level0 + (y * lw0) * nc;
                    for (int64_t i = x0 * nc; i < x1 * nc; i += 16) __builtin_prefetch(r + i);
                    __builtin_prefetch(r + x1 * nc - 1);
                }
        }
    };
    int members[CHUNK];
    bool done[CHUNK];
    std::vector<double> val(size_t(CHUNK * nc));
    double acc[NC > 0 ? NC : 64];
    for (int64_t ch = 0; ch < nc; ++ch) acc[ch] = 0.0;
    int64_t hits = 0, sub = 0, q = 0;  // the samples of pixel q summed so far
    const int64_t total = npix * ns;
    for (int64_t row = 0; row < total; row += row_len) {
        const int64_t row_end = std::min(total, row + row_len);
        for (int64_t c = row; c < row_end; c += CHUNK) {
            const int n = int(std::min<int64_t>(CHUNK, row_end - c));
            if (c != next_c) prepare(c, row_end, items_buf[cur]);
            Item* items = items_buf[cur];
            // the next chunk's footprints now, and their texels fetched into the cache while this one is integrated
            next_c = c + n < row_end ? c + n : row_end < total ? row_end : -1;
            if (next_c >= 0) prepare(next_c, next_c == row_end ? std::min(total, row_end + row_len) : row_end,
                                     items_buf[1 - cur]);
            cur = 1 - cur;
            for (int k = 0; k < n; ++k) done[k] = items[k].mode == 0;
            for (int k = 0; k < n; ++k) {
                if (done[k]) continue;
                const Item& it = items[k];
                const float* lbuf = (it.lev == 0 ? level0 : rest) + offsets[it.lev];
                const int64_t lh = shapes[2 * it.lev], lw = shapes[2 * it.lev + 1];
                double* v = val.data() + k * nc;
                if (it.mode == 2) {  // a footprint beyond the coarsest level, clipped by its window: the texels' weights
                    done[k] = true;
                    const int64_t nu = it.cols ? it.nwy : it.nwx, nv = it.cols ? it.nwx : it.nwy;
                    double* const w = wgt + STRIDE;  // row -1 of the weights is scratch
                    for (int64_t j = 0; j < nv + 2; ++j) std::fill(wgt + j * STRIDE, wgt + j * STRIDE + nu + LANES, 0.0);
                    if (it.cols) slice_weights(it.cy, it.cx, it.tay, it.tax, it.tby, it.tbx, it.wy0, it.wx0, nu, nv, w, STRIDE);
                    else slice_weights(it.cx, it.cy, it.tax, it.tay, it.tbx, it.tby, it.wx0, it.wy0, nu, nv, w, STRIDE);
                    double part[NC > 0 ? NC : 64];
                    for (int64_t ch = 0; ch < nc; ++ch) part[ch] = 0.0;
                    if (it.cols) gather<NC, true>(lbuf, lw, lh, nc, b, it.wx0, it.wy0, it.nwx, it.nwy, w, STRIDE, part);
                    else gather<NC, false>(lbuf, lw, lh, nc, b, it.wx0, it.wy0, it.nwx, it.nwy, w, STRIDE, part);
                    double sum = 0.0;  // some weights clipped: their sum, not the area
                    for (int64_t j = 0; j < nv; ++j)
                        for (int64_t i = 0; i < nu; ++i) sum += w[j * STRIDE + i];
                    const double norm = 1.0 / sum;
                    for (int64_t ch = 0; ch < nc; ++ch) v[ch] = part[ch] * norm;
                    continue;
                }
                // a shared window: this footprint and the later ones of the chunk at its level and slicing direction
                // whose windows fit with it
                int nm = 0;
                members[nm++] = k;
                done[k] = true;
                int64_t u0 = it.w.u0, u1 = it.w.u0 + it.w.nu, v0 = it.w.v0, v1 = it.w.v0 + it.w.nv;
                for (int k2 = k + 1; k2 < n; ++k2) {
                    const Item& o = items[k2];
                    if (done[k2] || o.mode != 1 || o.lev != it.lev || o.cols != it.cols) continue;
                    const int64_t a0 = std::min(u0, o.w.u0), a1 = std::max(u1, o.w.u0 + o.w.nu);
                    const int64_t b0 = std::min(v0, o.w.v0), b1 = std::max(v1, o.w.v0 + o.w.nv);
                    if (b1 - b0 > MAXR || (a1 - a0) * (b1 - b0) > CAP) continue;  // (a seam, a jump of the map)
                    u0 = a0; u1 = a1; v0 = b0; v1 = b1;
                    members[nm++] = k2;
                    done[k2] = true;
                }
                constexpr int64_t GROUP = NC > 0 ? NC : 4;  // channels integrated at once
                bool shared = false;  // G holds the shared window (a group with a texel not finite narrows it)
                for (int64_t c0 = 0; c0 < nc; c0 += GROUP) {
                    const int64_t cn = std::min(GROUP, nc - c0);
                    if (!shared) {  // every group of channels starts from the members' shared window
                        G.start(v0, v1);
                        for (int m = 0; m < nm; ++m) G.add(items[members[m]].w);
                        shared = true;
                    }
                    const bool finite = G.load(lbuf, lw, lh, nc, c0, cn, b, it.cols);
                    L carry{};  // the shared side of the last footprint, integrated from its frame (negated)
                    for (int m = 0; m < nm; ++m) {
                        const Item& o = items[members[m]];
                        if (!finite && nm > 1) {  // a texel not finite: this footprint through its own window alone
                            shared = false;
                            G.start(o.w.v0, o.w.v0 + o.w.nv);
                            G.add(o.w);
                            G.load(lbuf, lw, lh, nc, c0, cn, b, it.cols);
                        }
                        // the mean part * norm, within the texels the window read (where they are finite)
                        auto put = [&](const L& part, double norm) {
                            const L v = clamp_mean(part * norm, G.vmin, G.vmax);
                            double* vm = val.data() + members[m] * nc;
                            if constexpr (NC == 1) vm[0] = v;
                            else for (int64_t ch = 0; ch < cn; ++ch) vm[c0 + ch] = v[ch];
                        };
                        G.rows(o.w, R);
                        L part{};
                        if (o.sl || o.sr) {  // a quadrilateral: the contour V0 V1 V2 V3
                            double vx[4], vy[4];
                            for (int e = 0; e < 4; ++e) {
                                vx[e] = (o.cx - double(o.wx0)) + o.qx[e];
                                vy[e] = (o.cy - double(o.wy0)) + o.qy[e];
                            }
                            const double umax = double(o.w.nu - 2);
                            const int64_t jmax = o.w.nv - 2;
                            // its left side from the footprint before, when that one was just integrated
                            const bool have = o.sl && !o.seam && finite && m > 0 && members[m - 1] == members[m] - 1;
                            if (have) part = carry;
                            else directed_edge<NC>(vx[3], vy[3], vx[0], vy[0], umax, jmax, R, part);
                            directed_edge<NC>(vx[0], vy[0], vx[1], vy[1], umax, jmax, R, part);
                            directed_edge<NC>(vx[2], vy[2], vx[3], vy[3], umax, jmax, R, part);
                            L right{};
                            directed_edge<NC>(vx[1], vy[1], vx[2], vy[2], umax, jmax, R, right);
                            part = part + right;
                            carry = -right;
                            put(part, 2.0 / shoelace2(vx, vy));
                            continue;
                        }
                        const double area = o.cols ? prefix_slices<NC>(o.cy - double(o.wy0), o.cx - double(o.wx0), o.tay, o.tax,
                                                                       o.tby, o.tbx, o.w.nu, o.w.nv, R, part)
                                                   : prefix_slices<NC>(o.cx - double(o.wx0), o.cy - double(o.wy0), o.tax, o.tay,
                                                                       o.tbx, o.tby, o.w.nu, o.w.nv, R, part);
                        put(part, 1.0 / area);
                    }
                }
            }
            // the pixels' sums, in the samples' order
            for (int k = 0; k < n; ++k) {
                if (items[k].mode != 0) {
                    ++hits;
                    for (int64_t ch = 0; ch < nc; ++ch) acc[ch] += val[k * nc + ch];
                }
                if (++sub == ns) {  // the pixel's last sample
                    for (int64_t ch = 0; ch < nc; ++ch) { out[q * nc + ch] = float(acc[ch] * inv); acc[ch] = 0.0; }
                    alpha[q] = float(double(hits) * inv);
                    hits = 0;
                    sub = 0;
                    ++q;
                }
            }
        }
    }
}

}  // namespace

void footprint(const float* level0, const float* rest, const int64_t* shapes, const int64_t* offsets, int64_t nlev,
               int64_t nc, const float* xs, const float* ys, const bool* valid, const float* foot, int64_t npix,
               int64_t ns, int64_t row_len, Border b, double max_taps, float* out, float* alpha) {
    if (row_len <= 0 || row_len % ns != 0) row_len = ns;
    switch (nc) {
        case 1: return footprint_t<1>(level0, rest, shapes, offsets, nlev, nc, xs, ys, valid, foot, npix, ns, row_len, b, max_taps, out, alpha);
        case 3: return footprint_t<3>(level0, rest, shapes, offsets, nlev, nc, xs, ys, valid, foot, npix, ns, row_len, b, max_taps, out, alpha);
        case 4: return footprint_t<4>(level0, rest, shapes, offsets, nlev, nc, xs, ys, valid, foot, npix, ns, row_len, b, max_taps, out, alpha);
        default: return footprint_t<0>(level0, rest, shapes, offsets, nlev, nc, xs, ys, valid, foot, npix, ns, row_len, b, max_taps, out, alpha);
    }
}

}  // namespace lenslab

// The binding (lenslab.cxx_kernels.footprint), registered by src/native/module.cpp; the GIL is released.
namespace nb = nanobind;

void register_footprint(nb::module_& m) {
    using namespace lenslab;
    using namespace lenslab::bind;
    m.def("footprint", [](InF level0, InF rest, InI shapes, InI offsets, InF xs, InF ys, InB valid, InF foot,
                              bool wrap, bool top, bool bottom, double max_taps, OutF out, OutF alpha) {
        size_t npix = alpha.size();
        need(npix > 0 && xs.size() % npix == 0, "band shapes differ");
        size_t ns = xs.size() / npix;
        need(ys.size() == xs.size() && valid.size() == xs.size() && foot.size() == 4 * xs.size(), "band shapes differ");
        need(shapes.ndim() == 2 && shapes.shape(1) == 2 && shapes.shape(0) > 0 && offsets.size() == shapes.shape(0),
             "pyramid shapes");
        int64_t nc = int64_t(out.size() / npix);
        need(out.size() == npix * nc && nc > 0 && nc <= 64, "out must hold whole pixels (at most 64 channels)");
        const int64_t* sp = shapes.data();
        const int64_t* op = offsets.data();
        bool fits = op[0] == 0;  // every level lies inside its buffer
        for (size_t l = 0; l < shapes.shape(0); ++l) {
            const int64_t h = sp[2 * l], w = sp[2 * l + 1];
            fits &= h > 0 && w > 0 && h <= (int64_t(1) << 24) && w <= (int64_t(1) << 24) && op[l] >= 0;
            if (!fits) break;
            const uint64_t end = uint64_t(op[l]) + uint64_t(h * w) * uint64_t(nc);
            fits &= end <= (l == 0 ? level0.size() : rest.size());
        }
        need(fits, "the pyramid's levels must lie inside level0 and rest");
        need(max_taps > 0.0 && max_taps <= 8.0, "max_taps must be in (0, 8] (the window holds 2 max_taps + 3)");
        // an output row: xs (rows, width, ns) holds rows of width * ns samples; any other shape, one pixel
        const int64_t row_len = xs.ndim() == 3 && int64_t(xs.shape(2)) == int64_t(ns)
                                    ? int64_t(xs.shape(1)) * int64_t(ns) : int64_t(ns);
        {
            nb::gil_scoped_release release;
            footprint(level0.data(), rest.data(), shapes.data(), offsets.data(), int64_t(shapes.shape(0)), nc,
                      xs.data(), ys.data(), valid.data(), foot.data(), int64_t(npix), int64_t(ns), row_len,
                      {wrap, top, bottom}, max_taps, out.data(), alpha.data());
        }
    }, nb::arg("level0"), nb::arg("rest"), nb::arg("shapes"), nb::arg("offsets"), nb::arg("xs"), nb::arg("ys"),
       nb::arg("valid"), nb::arg("foot"), nb::arg("wrap"), nb::arg("top"), nb::arg("bottom"), nb::arg("max_taps"),
       nb::arg("out").noconvert(), nb::arg("alpha").noconvert());
}
