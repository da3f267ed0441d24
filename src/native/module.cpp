// Python bindings of the compiled kernels (lenslab.cxx_kernels). Every function releases the GIL: the engine
// runs one band of rows per thread. Arrays are C-contiguous and of the stated dtypes (checked by nanobind);
// inputs of another layout or dtype are converted, outputs never are (written in place, or refused).
#include <algorithm>
#include <cstring>
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>

#include <cmath>
#include <optional>
#include <stdexcept>

#include "bind.h"
#include "sampler.h"

namespace nb = nanobind;
using namespace lenslab;

void bind_map_kernels(nb::module_& m);  // bind_map.cpp: the map lattice and the separable samplers
void register_lens_kernels(nb::module_& m);  // lens_bindings.cpp: the lens models' kernels

using namespace lenslab::bind;  // In, Out, need

namespace {

// an image of sw x sh pixels of nc channels holds exactly `size` floats (no product overflows)
bool holds(size_t size, int64_t sw, int64_t sh, int64_t nc) {
    uint64_t px = 0, all = 0;
    return sw > 0 && sh > 0 && nc > 0 && !__builtin_mul_overflow(uint64_t(sw), uint64_t(sh), &px)
           && !__builtin_mul_overflow(px, uint64_t(nc), &all) && all == size;
}


}  // namespace

void register_tracer_paths(nb::module_& m);  // tracer_paths.cpp: the tracer's bounce loop
void register_video(nb::module_& m);  // video.cpp: the video colour passes
void register_video_ycbcr(nb::module_& m);  // video_ycbcr.cpp: Y'CbCr planes <-> linear light
void register_tone(nb::module_& m);  // tone.cpp
void register_footprint(nb::module_& m);  // src/native/footprint_runs.cpp
void register_secants(nb::module_& m);  // src/native/secants.cpp
void register_pyramid(nb::module_& m);  // src/native/pyramid.cpp: the pyramid's levels and the rows footprints read
void register_lens_dirs(nb::module_& m);  // lens_dirs.cpp: pixel -> direction of the closed-form lenses
void register_halves(nb::module_& m);  // halves.cpp: float32 -> float16 for the EXR writer

NB_MODULE(cxx_kernels, m) {
    register_video(m);
    register_video_ycbcr(m);
    m.doc() = "lenslab's compiled warp kernels (C++17): single-tap bilinear, cached taps, the footprint prefilter";
    bind_map_kernels(m);
    register_lens_kernels(m);
    register_tone(m);
    register_lens_dirs(m);
    register_halves(m);

    m.def("bilinear1", [](In<float> src, int64_t sw, int64_t sh, int64_t nc, In<float> xs, In<float> ys, In<bool> valid,
                          bool wrap, bool top, bool bottom, Out<float> out, Out<float> alpha, bool zeroed) {
        size_t n = xs.size();
        need(holds(src.size(), sw, sh, nc), "source size");
        need(ys.size() == n && valid.size() == n && alpha.size() == n && out.size() == n * nc, "band shapes differ");
        return bilinear1(src.data(), sw, sh, nc, xs.data(), ys.data(), valid.data(), int64_t(n), {wrap, top, bottom},
                         out.data(), alpha.data(), zeroed);
    }, nb::arg("src"), nb::arg("sw"), nb::arg("sh"), nb::arg("nc"), nb::arg("xs"), nb::arg("ys"), nb::arg("valid"), nb::arg("wrap"), nb::arg("top"), nb::arg("bottom"), nb::arg("out").noconvert(), nb::arg("alpha").noconvert(),
          nb::arg("zeroed") = false, nb::call_guard<nb::gil_scoped_release>());

    m.def("bilinear_n", [](In<float> src, int64_t sw, int64_t sh, int64_t nc, In<float> xs, In<float> ys,
                           In<bool> valid, bool wrap, bool top, bool bottom, Out<float> out, Out<float> alpha) {
        need(holds(src.size(), sw, sh, nc), "source size");
        size_t npix = alpha.size();
        need(npix > 0 && xs.size() % npix == 0, "band shapes differ");
        size_t ns = xs.size() / npix;
        need(ys.size() == xs.size() && valid.size() == xs.size() && out.size() == npix * nc && nc <= 64,
             "band shapes differ (or more than 64 channels)");
        bilinear_n(src.data(), sw, sh, nc, xs.data(), ys.data(), valid.data(), int64_t(npix), int64_t(ns),
                   {wrap, top, bottom}, out.data(), alpha.data());
    }, nb::arg("src"), nb::arg("sw"), nb::arg("sh"), nb::arg("nc"), nb::arg("xs"), nb::arg("ys"), nb::arg("valid"), nb::arg("wrap"), nb::arg("top"), nb::arg("bottom"), nb::arg("out").noconvert(), nb::arg("alpha").noconvert(),
          nb::call_guard<nb::gil_scoped_release>());

    m.def("taps_of", [](int64_t sw, int64_t sh, In<float> xs, In<float> ys, In<bool> valid, Out<uint32_t> off,
                        Out<float> tx, Out<float> ty) {
        size_t n = xs.size();
        need(ys.size() == n && valid.size() == n && off.size() == n && tx.size() == n && ty.size() == n,
             "band shapes differ");
        need(sw > 0 && sh > 0 && sw < int64_t(TAP_FOLDED) && sh < int64_t(TAP_FOLDED)
             && uint64_t(sw) * uint64_t(sh) < TAP_FOLDED, "taps need a source of fewer than 2^32 - 2 pixels");
        taps_of(sw, sh, xs.data(), ys.data(), valid.data(), int64_t(n), off.data(), tx.data(), ty.data());
    }, nb::arg("sw"), nb::arg("sh"), nb::arg("xs"), nb::arg("ys"), nb::arg("valid"), nb::arg("off").noconvert(), nb::arg("tx").noconvert(), nb::arg("ty").noconvert(),
          nb::call_guard<nb::gil_scoped_release>());

    m.def("from_taps", [](In<float> src, int64_t sw, int64_t nc, In<uint32_t> off, In<float> tx, In<float> ty,
                          Out<float> out, Out<float> alpha) {
        size_t n = off.size();
        need(sw > 0 && nc > 0 && src.size() % size_t(sw * nc) == 0, "source size");
        need(tx.size() == n && ty.size() == n && alpha.size() == n && out.size() == n * nc, "band shapes differ");
        const int64_t last = int64_t(src.size() / size_t(nc)) - sw - 1;  // a 2x2's top-left tap is below it
        const uint32_t* o = off.data();
        // an offset in [last, TAP_FOLDED) reads outside: one unsigned compare each, in a loop the compiler vectorises
        const uint32_t lo = uint32_t(std::clamp<int64_t>(last, 0, TAP_FOLDED)), span = TAP_FOLDED - lo;
        uint32_t outside = 0;
        for (size_t q = 0; q < n; ++q) outside |= uint32_t(uint32_t(o[q] - lo) < span);
        need(outside == 0, "a tap reads outside the source");
        from_taps(src.data(), sw, nc, off.data(), tx.data(), ty.data(), int64_t(n), out.data(), alpha.data());
    }, nb::arg("src"), nb::arg("sw"), nb::arg("nc"), nb::arg("off"), nb::arg("tx"), nb::arg("ty"), nb::arg("out").noconvert(), nb::arg("alpha").noconvert(),
          nb::call_guard<nb::gil_scoped_release>());

    m.def("folded", [](In<float> src, int64_t sw, int64_t sh, int64_t nc, In<int64_t> idx, In<float> xs, In<float> ys,
                       bool wrap, bool top, bool bottom, Out<float> out, Out<float> alpha) {
        size_t m_ = idx.size();
        need(holds(src.size(), sw, sh, nc), "source size");
        need(xs.size() == m_ && ys.size() == m_ && out.size() == alpha.size() * size_t(nc), "fold shapes differ");
        const int64_t* p = idx.data();
        for (size_t e = 0; e < m_; ++e) need(p[e] >= 0 && size_t(p[e]) < alpha.size(), "fold index out of range");
        folded(src.data(), sw, sh, nc, p, xs.data(), ys.data(), int64_t(m_), {wrap, top, bottom}, out.data(),
               alpha.data());
    }, nb::arg("src"), nb::arg("sw"), nb::arg("sh"), nb::arg("nc"), nb::arg("idx"), nb::arg("xs"), nb::arg("ys"), nb::arg("wrap"), nb::arg("top"), nb::arg("bottom"), nb::arg("out").noconvert(), nb::arg("alpha").noconvert(),
          nb::call_guard<nb::gil_scoped_release>());

    m.def("tap_reads", [](int64_t sw, int64_t sh, In<uint32_t> off, In<float> xs, In<float> ys, bool wrap, bool top,
                          bool bottom, Out<uint8_t> read) {
        need(sw > 0 && sh > 0 && uint64_t(sw) * uint64_t(sh) < TAP_FOLDED, "taps need a source of fewer than 2^32 - 2 pixels");
        need(xs.size() == ys.size() && read.size() == size_t(sw * sh), "read: the source's size");
        const uint32_t* o = off.data();
        const int64_t last = sw * (sh - 1) - 1;  // a 2x2's top-left tap is below it
        for (size_t q = 0; q < off.size(); ++q)
            need(o[q] >= TAP_FOLDED || int64_t(o[q]) < last, "a tap reads outside the source");
        tap_reads(sw, sh, o, int64_t(off.size()), xs.data(), ys.data(), int64_t(xs.size()), {wrap, top, bottom},
                  read.data());
    }, nb::arg("sw"), nb::arg("sh"), nb::arg("off"), nb::arg("xs"), nb::arg("ys"), nb::arg("wrap"), nb::arg("top"),
       nb::arg("bottom"), nb::arg("read").noconvert(), nb::call_guard<nb::gil_scoped_release>());

    m.def("read_spans", [](int64_t sw, int64_t sh, In<uint8_t> read, Out<int64_t> spans) {
        need(sw > 0 && sh > 0 && read.size() == size_t(sw * sh) && spans.size() == size_t(4 * sh), "read: sh x sw, spans: sh x 4");
        read_spans(sw, sh, read.data(), spans.data());
    }, nb::arg("sw"), nb::arg("sh"), nb::arg("read"), nb::arg("spans").noconvert(), nb::call_guard<nb::gil_scoped_release>());

    register_footprint(m);
    register_secants(m);
    register_pyramid(m);

    m.def("neighbour_secants", [](In<float> xs, In<float> ys, In<bool> vs, int64_t top, double wrap,
                                  In<int32_t> piece, Out<float> foot, Out<bool> edge, double far,
                                  std::optional<Out<int64_t>> coarse) {
        need(xs.ndim() == 2 && ys.ndim() == 2 && vs.ndim() == 2, "maps must be rows x width");
        const int64_t nrows = int64_t(xs.shape(0)), w = int64_t(xs.shape(1));
        need(int64_t(ys.shape(0)) == nrows && int64_t(vs.shape(0)) == nrows && int64_t(ys.shape(1)) == w
             && int64_t(vs.shape(1)) == w, "map shapes differ");
        need(w > 0 && edge.size() % size_t(w) == 0, "edge must hold whole rows");
        const int64_t h = int64_t(edge.size()) / w;
        need(foot.size() == size_t(4 * h * w) && top >= 0 && top + h <= nrows, "footprint rows");
        need(piece.size() == 0 || (piece.ndim() == 2 && int64_t(piece.shape(0)) == nrows
                                   && int64_t(piece.shape(1)) == w), "piece numbers must match the map");
        need(!coarse || coarse->size() == size_t(h * w), "coarse must hold an index for every pixel");
        nb::gil_scoped_release release;
        return neighbour_secants(xs.data(), ys.data(), vs.data(), nrows, w, top, h, wrap,
                                 piece.size() == 0 ? nullptr : piece.data(), foot.data(), edge.data(), far,
                                 coarse ? coarse->data() : nullptr);
    }, nb::arg("xs"), nb::arg("ys"), nb::arg("vs"), nb::arg("top"), nb::arg("wrap"), nb::arg("piece"),
       nb::arg("foot").noconvert(), nb::arg("edge").noconvert(), nb::arg("far") = INFINITY,
       nb::arg("coarse").noconvert() = nb::none());

    m.def("all_finite", [](In<float> a) {
        const float* p = a.data();
        const size_t n = a.size();
        // a float is NaN or infinite when its exponent bits are all set: an integer test the compiler vectorises
        // (std::isfinite's compare stays scalar here, 1.3 cycles a value)
        uint32_t bad = 0;
        for (size_t i = 0; i < n; ++i) {
            uint32_t bits;
            std::memcpy(&bits, p + i, sizeof bits);
            bad |= uint32_t((bits & 0x7f800000u) == 0x7f800000u);
        }
        return bad == 0;
    }, nb::arg("a"), nb::call_guard<nb::gil_scoped_release>());

    register_tracer_paths(m);
}
