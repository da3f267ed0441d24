// Python bindings of the map lattice and the separable samplers (lenslab.cxx_kernels): shapes, dtypes and every
// index a kernel will follow are checked here, before the GIL is released; outputs are written in place.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/pair.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "bind.h"
#include "kernels.h"
#include "lattice.h"

namespace nb = nanobind;
using namespace lenslab;

using namespace lenslab::bind;  // In, Out, need

namespace {

// every cell of cell rows lo..hi has a state of -1 to 2 (any other positive state would be read as a direction),
// and none is 2 (an interpolated direction) unless the band can hold its directions
void check_directions(const In<int8_t>& state, int64_t lo, int64_t hi, bool room) {
    const int64_t ncx = int64_t(state.shape(1));
    const int8_t* s = state.data();
    const int8_t top = room ? 2 : 1;
    bool ok = true;
    for (int64_t q = lo * ncx; q < (hi + 1) * ncx; ++q) ok &= s[q] >= -1 && s[q] <= top;
    need(ok, "cell states are -1 to 2, and cells that interpolate a direction need five coefficient sets and room "
             "for directions");
}

LatticeBand band_of(In<double> coef, In<int8_t> state, int64_t cb0, int64_t r0, In<double> offs, Out<float> xs,
                    Out<float> ys, Out<bool> valid, Out<int8_t> need_, Out<double> dirs, double inv) {
    need(state.ndim() == 2 && state.shape(0) > 0 && state.shape(1) > 0, "state must be cells x cells");
    const int64_t ncy = int64_t(state.shape(0)), ncx = int64_t(state.shape(1));
    need(coef.ndim() == 5 && int64_t(coef.shape(1)) == ncx && coef.shape(2) >= 2 && coef.shape(3) == 4
         && coef.shape(4) == 4 && coef.shape(0) > 0, "coef must be (rows, ncx, K, 4, 4)");
    const int64_t rows = int64_t(coef.shape(0)), nk = int64_t(coef.shape(2));
    need(xs.ndim() == 3, "xs must be (h, W, S)");
    const int64_t h = int64_t(xs.shape(0)), w = int64_t(xs.shape(1)), n = int64_t(xs.shape(2));
    const size_t total = size_t(h * w * n);
    need(ys.size() == total && valid.size() == total && need_.size() == total, "band shapes differ");
    need(offs.ndim() == 4 && offs.shape(0) > 0 && offs.shape(1) > 0 && int64_t(offs.shape(2)) == n
         && offs.shape(3) == 2, "offsets must be (ho, wo, S, 2)");
    const int64_t ho = int64_t(offs.shape(0)), wo = int64_t(offs.shape(1));
    need(wo == 1 || wo == w, "per-pixel offsets must cover the band's width");
    need(cb0 >= 0 && cb0 + rows <= ncy, "coefficient rows outside the lattice");
    // the cell rows the band reads: floor((r0 + r + oy) / step) is monotonic in r + oy
    const double* o = offs.data();
    double lo = o[1], hi = o[1];
    for (size_t q = 1; q < offs.size() / 2; ++q) {
        need(o[2 * q] == o[2 * q] && o[2 * q + 1] == o[2 * q + 1], "offsets must be numbers");
        lo = std::min(lo, o[2 * q + 1]);
        hi = std::max(hi, o[2 * q + 1]);
    }
    need(o[0] == o[0] && lo == lo && hi == hi && inv > 0.0, "offsets must be numbers, the step positive");
    // bounded, so that a cell's end column (lattice_rows: ceil(edge / inv - ox)) is an integer in range
    double far = 0.0;
    for (size_t q = 0; q < offs.size(); ++q) far = std::max(far, std::fabs(o[q]));
    need(far <= 2147483648.0 && inv >= 1.0 / 2147483648.0 && inv <= 2147483648.0 && r0 >= 0 && r0 <= (int64_t(1) << 40),
         "offsets beyond 2^31 pixels, a step beyond 2^31 or a first row beyond 2^40");
    auto cell = [&](double p) {
        p = std::floor(p);
        return !(p >= 0.0) ? int64_t(0) : (p >= double(ncy - 1) ? ncy - 1 : int64_t(p));
    };
    const int64_t first = h > 0 ? cell((double(r0) + lo) * inv) : cb0;
    const int64_t last = h > 0 ? cell((double(r0 + h - 1) + hi) * inv) : cb0;
    need(first >= cb0 && last < cb0 + rows, "the band reads cells beyond its coefficient rows");
    check_directions(state, first, last, nk >= 5 && dirs.size() >= 3 * total);
    return {coef.data(), nk, state.data(), ncy, ncx, cb0, offs.data(), ho, wo, h, w, n, r0,
            xs.data(), ys.data(), valid.data(), need_.data(), dirs.data()};
}

Pieces pieces_of(const In<int64_t>& table, const In<int64_t>& grid, int64_t cw, int64_t ch, int64_t sw, int64_t sh) {
    const int64_t np = table.ndim() == 2 ? int64_t(table.shape(0)) : 0;
    if (np == 0) return {table.data(), 0, grid.data(), 0, 0, 1, 1};
    need(table.shape(1) == 16, "the piece table has 16 columns");
    need(grid.ndim() == 2 && cw >= 1 && ch >= 1, "the piece grid must be rows x columns of cells");
    const int64_t* t = table.data();
    for (int64_t p = 0; p < np; ++p) {
        const int64_t* r = t + 16 * p;
        need(r[0] >= 0 && r[1] >= 0 && r[2] >= 1 && r[3] >= 1 && r[0] + r[2] <= sw && r[1] + r[3] <= sh,
             "a piece lies outside the image");
        for (int e = 0; e < 4; ++e)
            need(r[4 + 3 * e] >= -1 && r[4 + 3 * e] < np && (r[4 + 3 * e] < 0 || (r[5 + 3 * e] >= 0 && r[5 + 3 * e] < 4)),
                 "a piece's neighbour is not a piece");
    }
    const int64_t* g = grid.data();
    for (size_t q = 0; q < grid.size(); ++q) need(g[q] >= -1 && g[q] < np, "the piece grid names no piece");
    return {t, np, g, int64_t(grid.shape(0)), int64_t(grid.shape(1)), cw, ch};
}

}  // namespace

void bind_map_kernels(nb::module_& m) {
    m.def("ghost_pass", [](Out<double> gx, Out<double> gy, Out<bool> have, double wrap) {
        need(gx.ndim() == 2 && gy.size() == gx.size() && have.size() == gx.size(), "node arrays must match");
        ghost_pass(gx.data(), gy.data(), have.data(), int64_t(gx.shape(0)), int64_t(gx.shape(1)), wrap);
    }, nb::arg("gx").noconvert(), nb::arg("gy").noconvert(), nb::arg("have").noconvert(), nb::arg("wrap"),
       nb::call_guard<nb::gil_scoped_release>());

    m.def("lattice_grid", [](In<double> nx, In<double> ny, double tx, double ty, double wrap, Out<double> ox,
                             Out<double> oy) {
        need(nx.ndim() == 2 && nx.shape(0) >= 3 && nx.shape(1) >= 3 && ny.size() == nx.size(), "nodes must match");
        const int64_t rows = int64_t(nx.shape(0)), cols = int64_t(nx.shape(1));
        need(ox.size() == size_t((rows - 3) * (cols - 3)) && oy.size() == ox.size(), "one value per cell");
        lattice_grid(nx.data(), ny.data(), rows, cols, tx, ty, wrap, ox.data(), oy.data());
    }, nb::arg("nx"), nb::arg("ny"), nb::arg("tx"), nb::arg("ty"), nb::arg("wrap"), nb::arg("ox").noconvert(),
       nb::arg("oy").noconvert(), nb::call_guard<nb::gil_scoped_release>());

    m.def("cell_coefficients", [](In<double> nodes, In<int8_t> state, int64_t cb0, int64_t cb1, double wrap,
                                  Out<double> coef) {
        need(state.ndim() == 2 && nodes.ndim() == 3 && nodes.shape(0) >= 2, "nodes (K, rows, cols), state 2-d");
        const int64_t ncy = int64_t(state.shape(0)), ncx = int64_t(state.shape(1)), nk = int64_t(nodes.shape(0));
        need(int64_t(nodes.shape(1)) == ncy + 3 && int64_t(nodes.shape(2)) == ncx + 3, "nodes must frame the cells");
        need(cb0 >= 0 && cb0 <= cb1 && cb1 <= ncy, "cell rows outside the lattice");
        need(coef.ndim() == 5 && int64_t(coef.shape(0)) == cb1 - cb0 && int64_t(coef.shape(1)) == ncx
             && int64_t(coef.shape(2)) == nk && coef.shape(3) == 4 && coef.shape(4) == 4, "coef (rows, ncx, K, 4, 4)");
        if (cb1 > cb0) check_directions(state, cb0, cb1 - 1, nk >= 5);
        cell_coefficients(nodes.data(), nk, state.data(), ncy, ncx, cb0, cb1, wrap, coef.data());
    }, nb::arg("nodes"), nb::arg("state"), nb::arg("cb0"), nb::arg("cb1"), nb::arg("wrap"), nb::arg("coef").noconvert(),
       nb::call_guard<nb::gil_scoped_release>());

    m.def("lattice_eval", [](In<double> coef, In<int8_t> state, int64_t cb0, double step, int64_t r0, In<double> offs,
                             Out<float> xs, Out<float> ys, Out<bool> valid, Out<int8_t> need_, Out<double> dirs) {
        lattice_eval(band_of(coef, state, cb0, r0, offs, xs, ys, valid, need_, dirs, 1.0 / step), step);
    }, nb::arg("coef"), nb::arg("state"), nb::arg("cb0"), nb::arg("step"), nb::arg("r0"), nb::arg("offs"),
       nb::arg("xs").noconvert(), nb::arg("ys").noconvert(), nb::arg("valid").noconvert(), nb::arg("need").noconvert(),
       nb::arg("dirs").noconvert(), nb::call_guard<nb::gil_scoped_release>());

    m.def("lattice_rows", [](In<double> coef, In<int8_t> state, int64_t cb0, double inv, int64_t r0, In<double> offs,
                             Out<float> xs, Out<float> ys, Out<bool> valid, Out<int8_t> need_, Out<double> dirs) {
        need(offs.size() == 2 * (xs.ndim() == 3 ? xs.shape(2) : 0), "shared offsets must be (1, 1, S, 2)");
        lattice_rows(band_of(coef, state, cb0, r0, offs, xs, ys, valid, need_, dirs, inv), inv);
    }, nb::arg("coef"), nb::arg("state"), nb::arg("cb0"), nb::arg("inv"), nb::arg("r0"), nb::arg("offs"),
       nb::arg("xs").noconvert(), nb::arg("ys").noconvert(), nb::arg("valid").noconvert(), nb::arg("need").noconvert(),
       nb::arg("dirs").noconvert(), nb::call_guard<nb::gil_scoped_release>());

    m.def("outside_field", [](In<double> dirs, In<bool> have, In<bool> seen, In<double> axes, In<double> angles,
                              double bound, double slack, Out<bool> out) {
        const size_t ny = dirs.ndim() == 3 ? dirs.shape(0) : 0, nx = dirs.ndim() == 3 ? dirs.shape(1) : 0;
        need(ny >= 3 && nx >= 3 && dirs.shape(2) == 3 && have.size() == ny * nx && seen.size() == ny * nx,
             "outside_field: rays (ny, nx, 3) and their flags (ny, nx)");
        need(axes.size() == 3 * angles.size() && out.size() == (ny - 3) * (nx - 3), "outside_field: cones and cells");
        outside_field(dirs.data(), have.data(), seen.data(), int64_t(ny), int64_t(nx), axes.data(), angles.data(),
                      int64_t(angles.size()), bound, slack, out.data());
    }, nb::arg("dirs"), nb::arg("have"), nb::arg("seen"), nb::arg("axes"), nb::arg("angles"), nb::arg("bound"),
       nb::arg("slack"), nb::arg("out").noconvert(), nb::call_guard<nb::gil_scoped_release>());

    m.def("place", [](In<int64_t> at, In<double> xy, In<bool> v, Out<float> xs, Out<float> ys, Out<bool> valid) {
        const size_t n = at.size(), size = xs.size();
        need(xy.size() == 2 * n && v.size() == n, "place: xy (n, 2) and v (n,) for n positions");
        need(ys.size() == size && valid.size() == size, "place: xs, ys and valid differ in size");
        const int64_t* a = at.data();
        bool inside = true;
        for (size_t e = 0; e < n; ++e) inside &= a[e] >= 0 && size_t(a[e]) < size;
        need(inside, "place: a position beyond the maps");
        place(a, xy.data(), v.data(), int64_t(n), xs.data(), ys.data(), valid.data());
    }, nb::arg("at"), nb::arg("xy"), nb::arg("v"), nb::arg("xs").noconvert(), nb::arg("ys").noconvert(),
       nb::arg("valid").noconvert(), nb::call_guard<nb::gil_scoped_release>());

    m.def("thin_footprints", [](In<float> foot, float h2, float q2, Out<int64_t> idx) {
        const size_t n = foot.size() / 4;
        need(foot.size() == 4 * n && idx.size() >= n, "thin_footprints: foot (..., 4) and idx of one per footprint");
        return thin_footprints(foot.data(), int64_t(n), h2, q2, idx.data());
    }, nb::arg("foot"), nb::arg("h2"), nb::arg("q2"), nb::arg("idx").noconvert(), nb::call_guard<nb::gil_scoped_release>());

    m.def("fold_piece", [](int64_t i, int64_t j, int64_t p, In<int64_t> table) {
        need(table.ndim() == 2 && table.shape(1) == 16 && p >= 0 && p < int64_t(table.shape(0)), "no such piece");
        const int64_t np = int64_t(table.shape(0));
        for (int64_t q = 0; q < np; ++q)
            for (int e = 0; e < 4; ++e) need(table.data()[16 * q + 4 + 3 * e] < np, "a piece's neighbour is not a piece");
        fold_piece(i, j, p, table.data());
        return std::make_pair(i, j);
    }, nb::arg("i"), nb::arg("j"), nb::arg("p"), nb::arg("table"));

    m.def("separable", [](In<float> src, In<float> xs, In<float> ys, In<bool> valid, bool wrap, bool top, bool bottom,
                          In<int64_t> table, In<int64_t> grid, int64_t cw, int64_t ch, int kind, Out<float> out,
                          Out<float> alpha) {
        need(src.ndim() == 3 && src.shape(0) > 0 && src.shape(1) > 0 && src.shape(2) > 0, "src must be H x W x C");
        const int64_t sh = int64_t(src.shape(0)), sw = int64_t(src.shape(1)), nc = int64_t(src.shape(2));
        const size_t npix = alpha.size();
        need(npix > 0 && xs.size() % npix == 0 && ys.size() == xs.size() && valid.size() == xs.size()
             && out.size() == npix * size_t(nc), "band shapes differ");
        need(kind >= 0 && kind <= 3, "filter kind 0 to 3");
        const Pieces pc = pieces_of(table, grid, cw, ch, sw, sh);
        separable(src.data(), sw, sh, nc, xs.data(), ys.data(), valid.data(), int64_t(npix),
                  int64_t(xs.size() / npix), wrap, top, bottom, pc, kind, out.data(), alpha.data());
    }, nb::arg("src"), nb::arg("xs"), nb::arg("ys"), nb::arg("valid"), nb::arg("wrap"), nb::arg("top"),
       nb::arg("bottom"), nb::arg("table"), nb::arg("grid"), nb::arg("cw"), nb::arg("ch"), nb::arg("kind"),
       nb::arg("out").noconvert(), nb::arg("alpha").noconvert(), nb::call_guard<nb::gil_scoped_release>());
    m.def("axis_weights", [](int kind, In<double> xs, Out<double> w) {
        need(kind >= 1 && kind <= 3 && w.size() == xs.size() * size_t(2 * kind), "kind 1 to 3; w (n, 2 kind)");
        for (size_t q = 0; q < xs.size(); ++q) axis_weights(kind, xs.data()[q], w.data() + q * size_t(2 * kind));
    }, nb::arg("kind"), nb::arg("xs"), nb::arg("w").noconvert(), nb::call_guard<nb::gil_scoped_release>());
}
