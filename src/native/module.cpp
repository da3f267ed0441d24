// Python bindings of the compiled kernels (lenslab.cxx_kernels). Every function releases the GIL: the engine
// runs one band of rows per thread. Arrays are C-contiguous and of the stated dtypes (checked by nanobind);
// inputs of another layout or dtype are converted, outputs never are (written in place, or refused).
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cmath>
#include <stdexcept>

#include "sampler.h"

namespace nb = nanobind;
using namespace lenslab;

void bind_map_kernels(nb::module_& m);  // bind_map.cpp: the map lattice and the separable samplers
void register_lens_kernels(nb::module_& m);  // lens_bindings.cpp: the lens models' kernels

template <typename T> using In = nb::ndarray<const T, nb::c_contig, nb::device::cpu>;
template <typename T> using Out = nb::ndarray<T, nb::c_contig, nb::device::cpu>;

namespace {

void need(bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(what);
}


}  // namespace

void register_tracer_paths(nb::module_& m);  // tracer_paths.cpp: the tracer's bounce loop
void register_video(nb::module_& m);  // video.cpp: the video colour passes
void register_video_ycbcr(nb::module_& m);  // video_ycbcr.cpp: Y'CbCr planes <-> linear light
void register_tone(nb::module_& m);  // tone.cpp

NB_MODULE(cxx_kernels, m) {
    register_video(m);
    register_video_ycbcr(m);
    m.doc() = "lenslab's compiled warp kernels (C++17): single-tap bilinear, cached taps, the footprint prefilter";
    bind_map_kernels(m);
    register_lens_kernels(m);
    register_tone(m);

    m.def("bilinear1", [](In<float> src, int64_t sw, int64_t sh, int64_t nc, In<float> xs, In<float> ys, In<bool> valid,
                          bool wrap, bool top, bool bottom, Out<float> out, Out<float> alpha) {
        size_t n = xs.size();
        need(ys.size() == n && valid.size() == n && alpha.size() == n && out.size() == n * nc, "band shapes differ");
        need(src.size() == size_t(sw * sh * nc), "source size");
        bilinear1(src.data(), sw, sh, nc, xs.data(), ys.data(), valid.data(), int64_t(n), {wrap, top, bottom},
                  out.data(), alpha.data());
    }, nb::arg("src"), nb::arg("sw"), nb::arg("sh"), nb::arg("nc"), nb::arg("xs"), nb::arg("ys"), nb::arg("valid"), nb::arg("wrap"), nb::arg("top"), nb::arg("bottom"), nb::arg("out").noconvert(), nb::arg("alpha").noconvert(),
          nb::call_guard<nb::gil_scoped_release>());

    m.def("bilinear_n", [](In<float> src, int64_t sw, int64_t sh, int64_t nc, In<float> xs, In<float> ys,
                           In<bool> valid, bool wrap, bool top, bool bottom, Out<float> out, Out<float> alpha) {
        size_t npix = alpha.size();
        need(npix > 0 && xs.size() % npix == 0, "band shapes differ");
        size_t ns = xs.size() / npix;
        need(ys.size() == xs.size() && valid.size() == xs.size() && out.size() == npix * nc && nc <= 64,
             "band shapes differ (or more than 64 channels)");
        need(src.size() == size_t(sw * sh * nc), "source size");
        bilinear_n(src.data(), sw, sh, nc, xs.data(), ys.data(), valid.data(), int64_t(npix), int64_t(ns),
                   {wrap, top, bottom}, out.data(), alpha.data());
    }, nb::arg("src"), nb::arg("sw"), nb::arg("sh"), nb::arg("nc"), nb::arg("xs"), nb::arg("ys"), nb::arg("valid"), nb::arg("wrap"), nb::arg("top"), nb::arg("bottom"), nb::arg("out").noconvert(), nb::arg("alpha").noconvert(),
          nb::call_guard<nb::gil_scoped_release>());

    m.def("taps_of", [](int64_t sw, int64_t sh, In<float> xs, In<float> ys, In<bool> valid, Out<uint32_t> off,
                        Out<float> tx, Out<float> ty) {
        size_t n = xs.size();
        need(ys.size() == n && valid.size() == n && off.size() == n && tx.size() == n && ty.size() == n,
             "band shapes differ");
        taps_of(sw, sh, xs.data(), ys.data(), valid.data(), int64_t(n), off.data(), tx.data(), ty.data());
    }, nb::arg("sw"), nb::arg("sh"), nb::arg("xs"), nb::arg("ys"), nb::arg("valid"), nb::arg("off").noconvert(), nb::arg("tx").noconvert(), nb::arg("ty").noconvert(),
          nb::call_guard<nb::gil_scoped_release>());

    m.def("from_taps", [](In<float> src, int64_t sw, int64_t nc, In<uint32_t> off, In<float> tx, In<float> ty,
                          Out<float> out, Out<float> alpha) {
        size_t n = off.size();
        need(tx.size() == n && ty.size() == n && alpha.size() == n && out.size() == n * nc, "band shapes differ");
        from_taps(src.data(), sw, nc, off.data(), tx.data(), ty.data(), int64_t(n), out.data(), alpha.data());
    }, nb::arg("src"), nb::arg("sw"), nb::arg("nc"), nb::arg("off"), nb::arg("tx"), nb::arg("ty"), nb::arg("out").noconvert(), nb::arg("alpha").noconvert(),
          nb::call_guard<nb::gil_scoped_release>());

    m.def("folded", [](In<float> src, int64_t sw, int64_t sh, int64_t nc, In<int64_t> idx, In<float> xs, In<float> ys,
                       bool wrap, bool top, bool bottom, Out<float> out, Out<float> alpha) {
        size_t m_ = idx.size();
        need(xs.size() == m_ && ys.size() == m_, "fold shapes differ");
        const int64_t* p = idx.data();
        for (size_t e = 0; e < m_; ++e) need(p[e] >= 0 && size_t(p[e]) < alpha.size(), "fold index out of range");
        folded(src.data(), sw, sh, nc, p, xs.data(), ys.data(), int64_t(m_), {wrap, top, bottom}, out.data(),
               alpha.data());
    }, nb::arg("src"), nb::arg("sw"), nb::arg("sh"), nb::arg("nc"), nb::arg("idx"), nb::arg("xs"), nb::arg("ys"), nb::arg("wrap"), nb::arg("top"), nb::arg("bottom"), nb::arg("out").noconvert(), nb::arg("alpha").noconvert(),
          nb::call_guard<nb::gil_scoped_release>());

    m.def("footprint", [](In<float> level0, In<float> rest, In<int64_t> shapes, In<int64_t> offsets, In<float> xs,
                          In<float> ys, In<bool> valid, In<float> foot, bool wrap, bool top, bool bottom,
                          double max_taps, double density, double axis_tol, Out<float> out, Out<float> alpha) {
        size_t npix = alpha.size();
        need(npix > 0 && xs.size() % npix == 0, "band shapes differ");
        size_t ns = xs.size() / npix;
        need(ys.size() == xs.size() && valid.size() == xs.size() && foot.size() == 4 * xs.size(), "band shapes differ");
        need(shapes.ndim() == 2 && shapes.shape(1) == 2 && offsets.size() == shapes.shape(0), "pyramid shapes");
        int64_t nc = int64_t(out.size() / npix);
        need(out.size() == npix * nc && nc <= 64, "out must hold whole pixels (at most 64 channels)");
        footprint(level0.data(), rest.data(), shapes.data(), offsets.data(), int64_t(shapes.shape(0)), nc, xs.data(),
                  ys.data(), valid.data(), foot.data(), int64_t(npix), int64_t(ns), {wrap, top, bottom},
                  {max_taps, density, axis_tol}, out.data(), alpha.data());
    }, nb::arg("level0"), nb::arg("rest"), nb::arg("shapes"), nb::arg("offsets"), nb::arg("xs"), nb::arg("ys"), nb::arg("valid"), nb::arg("foot"), nb::arg("wrap"), nb::arg("top"), nb::arg("bottom"), nb::arg("max_taps"), nb::arg("density"), nb::arg("axis_tol"), nb::arg("out").noconvert(), nb::arg("alpha").noconvert(),
          nb::call_guard<nb::gil_scoped_release>());

    m.def("neighbour_secants", [](In<float> xs, In<float> ys, In<bool> vs, int64_t top, double wrap,
                                  In<int32_t> piece, Out<float> foot, Out<bool> edge) {
        need(xs.ndim() == 2 && ys.ndim() == 2 && vs.ndim() == 2, "maps must be rows x width");
        const int64_t nrows = int64_t(xs.shape(0)), w = int64_t(xs.shape(1));
        need(int64_t(ys.shape(0)) == nrows && int64_t(vs.shape(0)) == nrows && int64_t(ys.shape(1)) == w
             && int64_t(vs.shape(1)) == w, "map shapes differ");
        need(w > 0 && edge.size() % size_t(w) == 0, "edge must hold whole rows");
        const int64_t h = int64_t(edge.size()) / w;
        need(foot.size() == size_t(4 * h * w) && top >= 0 && top + h <= nrows, "footprint rows");
        need(piece.size() == 0 || (piece.ndim() == 2 && int64_t(piece.shape(0)) == nrows
                                   && int64_t(piece.shape(1)) == w), "piece numbers must match the map");
        neighbour_secants(xs.data(), ys.data(), vs.data(), nrows, w, top, h, wrap,
                          piece.size() == 0 ? nullptr : piece.data(), foot.data(), edge.data());
    }, nb::arg("xs"), nb::arg("ys"), nb::arg("vs"), nb::arg("top"), nb::arg("wrap"), nb::arg("piece"),
       nb::arg("foot").noconvert(), nb::arg("edge").noconvert(),
       nb::call_guard<nb::gil_scoped_release>());

    m.def("all_finite", [](In<float> a) {
        const float* p = a.data();
        const size_t n = a.size();
        bool ok = true;
        for (size_t i = 0; i < n; ++i) ok &= std::isfinite(p[i]);  // branch-free: vectorised
        return ok;
    }, nb::arg("a"), nb::call_guard<nb::gil_scoped_release>());

    m.def("edges", [](In<float> src, int64_t sw, int64_t sh, int64_t nc, In<int64_t> idx, In<float> exs, In<float> eys,
                      In<bool> evalid, int64_t ns, bool wrap, bool top, bool bottom, Out<float> out, Out<float> alpha) {
        size_t m_ = idx.size();
        need(m_ == 0 || exs.size() % m_ == 0, "edge shapes differ");
        size_t kk = m_ ? exs.size() / m_ : 0;
        need(eys.size() == exs.size() && evalid.size() == exs.size(), "edge shapes differ");
        const int64_t* p = idx.data();
        for (size_t e = 0; e < m_; ++e) need(p[e] >= 0 && size_t(p[e] / ns) < alpha.size(), "edge index out of range");
        edges(src.data(), sw, sh, nc, p, exs.data(), eys.data(), evalid.data(), int64_t(m_), int64_t(kk), ns, 0,
              {wrap, top, bottom}, out.data(), alpha.data());
    }, nb::arg("src"), nb::arg("sw"), nb::arg("sh"), nb::arg("nc"), nb::arg("idx"), nb::arg("exs"), nb::arg("eys"), nb::arg("evalid"), nb::arg("ns"), nb::arg("wrap"), nb::arg("top"), nb::arg("bottom"), nb::arg("out").noconvert(), nb::arg("alpha").noconvert(),
          nb::call_guard<nb::gil_scoped_release>());

    register_tracer_paths(m);
}
