// Python bindings of the tracer's bounce loop (tracer_paths.h): lenslab.cxx_kernels.LambertScene, registered by
// register_tracer_paths from module.cpp. Every pass checks its arrays' shapes, then releases the GIL: a render's
// bands run on threads. Built with -ffp-contract=off (CMakeLists.txt), as tracer_paths.h requires.
#include "tracer_paths.h"

#include <nanobind/stl/pair.h>

namespace nb = nanobind;
using namespace lenslab_tracer;

namespace {

// rows of an (n, w) array, its width checked
template <typename A> int64_t rows(const A& a, int64_t w, const char* what) {
    need(a.size() % size_t(w) == 0, what);
    return int64_t(a.size() / size_t(w));
}

}  // namespace

void register_tracer_paths(nb::module_& m) {
    m.attr("LAMBERT_PACKET") = K;  // the rays per closest-hit query: rtcIntersect<K> (and rtcOccluded1)
    nb::class_<LambertScene>(m, "LambertScene",
                             "The tracer's bounce loop in a Lambertian scene lit by area lights (tracer.wavefront).")
        .def(nb::init<uintptr_t, uintptr_t, uintptr_t, In<float>, In<int32_t>, In<bool>, In<bool>, In<float>,
                      In<float>, In<float>, In<double>, In<int64_t>, In<float>, In<float>, In<float>>(),
             nb::arg("scene"), nb::arg("intersect"), nb::arg("occluded"), nb::arg("normals"),
             nb::arg("material_ids"), nb::arg("emissive"), nb::arg("two_sided"), nb::arg("light_area_pdf"),
             nb::arg("emission"), nb::arg("kd"), nb::arg("cdf"), nb::arg("light_tris"), nb::arg("v0"),
             nb::arg("e1"), nb::arg("e2"))
        .def("intersect", [](const LambertScene& sc, In<float> o, In<float> d, int64_t n, Out<int32_t> prim,
                             Out<float> t) {
            need(n >= 0 && rows(o, 3, "o is (N, 3)") >= n && rows(d, 3, "d is (N, 3)") >= n
                 && int64_t(prim.size()) >= n && int64_t(t.size()) >= n, "ray arrays shorter than n");
            nb::gil_scoped_release unlocked;
            sc.intersect(o.data(), d.data(), n, prim.data(), t.data());
        }, nb::arg("o"), nb::arg("d"), nb::arg("n"), nb::arg("prim").noconvert(), nb::arg("t").noconvert(),
           "Closest hits of rays 0..n: triangle (-1 for none) and distance (inf for none).")
        .def("shade", [](const LambertScene& sc, In<int32_t> prim, In<float> t, Out<float> o, Out<float> d,
                         Out<float> beta, Out<float> L, Out<float> prev_pdf, In<bool> specular, Out<int64_t> idx,
                         Out<float> out, In<float> u_nee, In<float> u_bsdf, In<float> cphi, In<float> sphi,
                         In<float> u_rr, float p_area, float eps, float eps2, bool last, bool rr, Out<bool> alive,
                         Out<int64_t> sh_rows, Out<float> sh_o, Out<float> sh_d, Out<float> sh_t,
                         Out<float> sh_val) {
            const int64_t n = int64_t(prim.size());
            need(int64_t(t.size()) == n, "prim and t differ");
            for (auto cap : {rows(o, 3, "o is (N, 3)"), rows(d, 3, "d is (N, 3)"), rows(beta, 3, "beta is (N, 3)"),
                             rows(L, 3, "L is (N, 3)"), int64_t(prev_pdf.size()), int64_t(specular.size()),
                             int64_t(idx.size()), int64_t(alive.size()), int64_t(sh_rows.size()),
                             rows(sh_o, 3, "sh_o is (N, 3)"), rows(sh_d, 3, "sh_d is (N, 3)"), int64_t(sh_t.size()),
                             rows(sh_val, 3, "sh_val is (N, 3)")})
                need(cap >= n, "path arrays shorter than the live paths");
            int64_t hits = 0;
            for (size_t i = 0; i < prim.size(); ++i) hits += prim.data()[i] >= 0;
            if (!last)
                need(rows(u_nee, 4, "u_nee is (M, 4)") >= hits && rows(u_bsdf, 3, "u_bsdf is (M, 3)") >= hits
                     && int64_t(cphi.size()) >= hits && int64_t(sphi.size()) >= hits
                     && (!rr || int64_t(u_rr.size()) >= hits), "fewer random numbers than hits");
            const LambertScene::State s{o.data(), d.data(), beta.data(), L.data(), prev_pdf.data(), rows(L, 3, "L"),
                                        specular.data(),
                                        idx.data(), out.data(), rows(out, 3, "out is (N, 3)"), alive.data(),
                                        sh_rows.data(), sh_o.data(), sh_d.data(), sh_t.data(), sh_val.data()};
            nb::gil_scoped_release unlocked;
            return sc.shade(prim.data(), t.data(), n, s, u_nee.data(), u_bsdf.data(), cphi.data(), sphi.data(),
                            u_rr.data(), p_area, eps, eps2, last, rr);
        }, nb::arg("prim"), nb::arg("t"), nb::arg("o").noconvert(), nb::arg("d").noconvert(),
           nb::arg("beta").noconvert(), nb::arg("L").noconvert(), nb::arg("prev_pdf").noconvert(),
           nb::arg("specular"), nb::arg("idx").noconvert(), nb::arg("out").noconvert(), nb::arg("u_nee"),
           nb::arg("u_bsdf"), nb::arg("cphi"), nb::arg("sphi"), nb::arg("u_rr"), nb::arg("p_area"), nb::arg("eps"),
           nb::arg("eps2"), nb::arg("last"), nb::arg("rr"), nb::arg("alive").noconvert(),
           nb::arg("sh_rows").noconvert(), nb::arg("sh_o").noconvert(), nb::arg("sh_d").noconvert(),
           nb::arg("sh_t").noconvert(), nb::arg("sh_val").noconvert(),
           "One bounce of the live paths in place; (paths shaded, shadow rays).")
        .def("settle", [](const LambertScene& sc, int64_t m, Out<int64_t> idx, Out<float> o, Out<float> d,
                          Out<float> beta, Out<float> L, Out<float> prev_pdf, In<bool> alive, int64_t g,
                          In<int64_t> sh_rows, In<float> sh_o, In<float> sh_d, In<float> sh_t, In<float> sh_val,
                          Out<float> out) {
            for (auto cap : {rows(o, 3, "o is (N, 3)"), rows(d, 3, "d is (N, 3)"), rows(beta, 3, "beta is (N, 3)"),
                             rows(L, 3, "L is (N, 3)"), int64_t(prev_pdf.size()), int64_t(idx.size()),
                             int64_t(alive.size())})
                need(m >= 0 && cap >= m, "path arrays shorter than m");
            for (auto cap : {int64_t(sh_rows.size()), rows(sh_o, 3, "sh_o is (N, 3)"), rows(sh_d, 3, "sh_d is (N, 3)"),
                             int64_t(sh_t.size()), rows(sh_val, 3, "sh_val is (N, 3)")})
                need(g >= 0 && cap >= g, "shadow ray arrays shorter than g");
            const LambertScene::State s{o.data(), d.data(), beta.data(), L.data(), prev_pdf.data(), rows(L, 3, "L"),
                                        nullptr,
                                        idx.data(), out.data(), rows(out, 3, "out is (N, 3)"),
                                        const_cast<bool*>(alive.data()), const_cast<int64_t*>(sh_rows.data()),
                                        const_cast<float*>(sh_o.data()), const_cast<float*>(sh_d.data()),
                                        const_cast<float*>(sh_t.data()), const_cast<float*>(sh_val.data())};
            nb::gil_scoped_release unlocked;
            return sc.settle(m, g, s);
        }, nb::arg("m"), nb::arg("idx").noconvert(), nb::arg("o").noconvert(), nb::arg("d").noconvert(),
           nb::arg("beta").noconvert(), nb::arg("L").noconvert(), nb::arg("prev_pdf").noconvert(), nb::arg("alive"),
           nb::arg("g"), nb::arg("sh_rows"), nb::arg("sh_o"), nb::arg("sh_d"), nb::arg("sh_t"), nb::arg("sh_val"),
           nb::arg("out").noconvert(),
           "Shadow rays cast, visible light added, finished paths written out, the rest moved up; their count.");
}
