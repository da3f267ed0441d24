// Python bindings of the lens models' kernels (lens_kernels.h), registered into lenslab.cxx_kernels by
// register_lens_kernels(). Every function releases the GIL. Inputs are float64 (converted if need be);
// outputs are C-contiguous float64 / bool arrays written in place (never converted).
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/tuple.h>

#include <cmath>
#include <stdexcept>
#include <utility>

#include "bind.h"
#include "lens_kernels.h"

namespace nb = nanobind;
using namespace lenslab::lens;

using namespace lenslab::bind;  // In, Out, need

namespace {

using Vec = In<double>;

// n points of `dim` coordinates in `pts`, and outputs of `odim` coordinates and one flag each
int64_t points(const Vec& pts, size_t dim, const Out<double>& out, size_t odim, const Out<bool>& ok) {
    need(pts.size() % dim == 0, "points must be rows of coordinates");
    const size_t n = pts.size() / dim;
    need(out.size() == n * odim && ok.size() == n, "outputs must hold one row per point");
    return int64_t(n);
}

// a whole number 0..hi held in a double, else -1 (NaN, a fraction or a value out of range is never converted)
int64_t whole(double v, int64_t hi) { return v >= 0.0 && v <= double(hi) && v == std::floor(v) ? int64_t(v) : -1; }

Table table_of(const Vec& t, double step) {
    need(t.size() >= 2, "the table of the inverse needs two entries or more");
    need(step > 0.0 && std::isfinite(step), "the table's step must be a positive number");  // else a negative index
    return {t.data(), int64_t(t.size()), step};
}

// a projection's parameters q: the first three (the most any projection has), padded with zeros
struct Q3 { double v[3]; };
Q3 q3(const Vec& q) {
    Q3 o{{0.0, 0.0, 0.0}};
    for (size_t i = 0; i < q.size() && i < 3; ++i) o.v[i] = q.data()[i];
    return o;
}

Distortion distortion_of(const Vec& a, const Vec& b, double p1, double p2, const Vec& s, bool tangential, double fold) {
    need(a.size() == 4 && b.size() == 3 && s.size() == 4, "distortion: a has 4 terms, b 3 and s 4");
    return {a.data(), b.data(), p1, p2, s.data(), tangential, fold};
}

}  // namespace

void register_lens_kernels(nb::module_& m) {
    using nb::arg;
    const auto release = nb::call_guard<nb::gil_scoped_release>();

    static const std::pair<const char*, int64_t> code_list[] = {
        {"RECTILINEAR", RECTILINEAR}, {"EQUIRECTANGULAR", EQUIRECTANGULAR}, {"CYLINDRICAL", CYLINDRICAL},
        {"EQUIDISTANT", EQUIDISTANT}, {"EQUISOLID", EQUISOLID}, {"STEREOGRAPHIC", STEREOGRAPHIC},
        {"ORTHOGRAPHIC", ORTHOGRAPHIC}, {"THOBY", THOBY}, {"UNIFIED", UNIFIED}, {"DOUBLE_SPHERE", DOUBLE_SPHERE},
        {"EUCM", EUCM}, {"FOV", FOV}, {"EQUAL_AREA_CYLINDRICAL", EQUAL_AREA_CYLINDRICAL}, {"MERCATOR", MERCATOR},
        {"DIVISION", DIVISION}, {"DIVISION_RECIPROCAL", DIVISION_RECIPROCAL}, {"BROWN", BROWN},
        {"TAN_FISHEYE", TAN_FISHEYE}, {"RATIONAL", RATIONAL}, {"OCAM", OCAM}};
    nb::dict codes;  // the codes the kernels dispatch on (lenslab.lenses.formulas.kinds, .solve)
    for (const auto& [name, v] : code_list) codes[name] = v;
    m.attr("lens_codes") = codes;
    m.attr("THOBY_K") = nb::make_tuple(THOBY_K1, THOBY_K2);

    m.def("equirect_pixels", [](Vec d, Vec p, Out<double> xy, Out<bool> ok) {
        need(p.size() == 9, "equirect: 9 parameters");
        equirect_pixels(d.data(), points(d, 3, xy, 2, ok), p.data(), xy.data(), ok.data());
    }, arg("d"), arg("params"), arg("xy").noconvert(), arg("ok").noconvert(), release,
       "Equirect directions (any length; zero and non-finite invalid) -> pixels (the lens's PixelKernel).");

    m.def("perspective_pixels", [](Vec d, Vec p, Out<double> xy, Out<bool> ok) {
        need(p.size() == 6, "perspective: 6 parameters");
        perspective_pixels(d.data(), points(d, 3, xy, 2, ok), p.data(), xy.data(), ok.data());
    }, arg("d"), arg("params"), arg("xy").noconvert(), arg("ok").noconvert(), release,
       "Perspective directions (any length; zero and non-finite invalid) -> pixels (the lens's PixelKernel).");

    m.def("hammer_pixels", [](Vec d, Vec p, Out<double> xy, Out<bool> ok) {
        need(p.size() == 4, "hammer: 4 parameters");
        hammer_pixels(d.data(), points(d, 3, xy, 2, ok), p.data(), xy.data(), ok.data());
    }, arg("d"), arg("params"), arg("xy").noconvert(), arg("ok").noconvert(), release,
       "Hammer directions (any length; zero and non-finite invalid) -> pixels (the lens's PixelKernel).");

    m.def("fisheye_pixels", [](Vec d, Vec p, Out<double> xy, Out<bool> ok) {
        need(p.size() == 21, "fisheye: 21 parameters");
        need(whole(p.data()[3], 64) >= 0, "fisheye: the mapping code must be a whole number");
        fisheye_pixels(d.data(), points(d, 3, xy, 2, ok), p.data(), xy.data(), ok.data());
    }, arg("d"), arg("params"), arg("xy").noconvert(), arg("ok").noconvert(), release,
       "Fisheye directions (any length; zero and non-finite invalid) -> pixels (the lens's PixelKernel).");

    m.def("dual_fisheye_pixels", [](Vec d, Vec p, Out<double> xy, Out<bool> ok) {
        need(p.size() == 10, "dual fisheye: 10 parameters");
        need(whole(p.data()[3], 64) >= 0, "dual fisheye: the mapping code must be a whole number");
        dual_fisheye_pixels(d.data(), points(d, 3, xy, 2, ok), p.data(), xy.data(), ok.data());
    }, arg("d"), arg("params"), arg("xy").noconvert(), arg("ok").noconvert(), release,
       "Dual-fisheye directions (any length; zero and non-finite invalid) -> pixels (the lens's PixelKernel).");

    m.def("sinusoidal_pixels", [](Vec d, Vec p, Out<double> xy, Out<bool> ok) {
        need(p.size() == 4, "sinusoidal: 4 parameters");
        sinusoidal_pixels(d.data(), points(d, 3, xy, 2, ok), p.data(), xy.data(), ok.data());
    }, arg("d"), arg("params"), arg("xy").noconvert(), arg("ok").noconvert(), release,
       "Sinusoidal directions (any length; zero and non-finite invalid) -> pixels (the lens's PixelKernel).");

    m.def("pannini_pixels", [](Vec d, Vec p, Out<double> xy, Out<bool> ok) {
        need(p.size() == 8, "pannini: 8 parameters");
        pannini_pixels(d.data(), points(d, 3, xy, 2, ok), p.data(), xy.data(), ok.data());
    }, arg("d"), arg("params"), arg("xy").noconvert(), arg("ok").noconvert(), release,
       "Pannini directions (any length; zero and non-finite invalid) -> pixels (the lens's PixelKernel).");

    m.def("swirl_pixels", [](Vec d, Vec p, Out<double> xy, Out<bool> ok) {
        need(p.size() == 7, "swirl: 7 parameters");
        swirl_pixels(d.data(), points(d, 3, xy, 2, ok), p.data(), xy.data(), ok.data());
    }, arg("d"), arg("params"), arg("xy").noconvert(), arg("ok").noconvert(), release,
       "Swirled pinhole directions (any length; zero and non-finite invalid) -> pixels (the lens's PixelKernel).");

    m.def("cylinder_pixels", [](Vec d, Vec p, Out<double> xy, Out<bool> ok) {
        need(p.size() == 8, "cylinder: 8 parameters");
        need(whole(p.data()[3], 64) >= 0, "cylinder: the projection code must be a whole number");
        cylinder_pixels(d.data(), points(d, 3, xy, 2, ok), p.data(), xy.data(), ok.data());
    }, arg("d"), arg("params"), arg("xy").noconvert(), arg("ok").noconvert(), release,
       "Cylinder directions (any length; zero and non-finite invalid) -> pixels (the lens's PixelKernel).");

    m.def("brown_pixels", [](Vec d, Vec p, Out<double> xy, Out<bool> ok) {
        need(p.size() == 9, "brown: 9 parameters");
        brown_pixels(d.data(), points(d, 3, xy, 2, ok), p.data(), xy.data(), ok.data());
    }, arg("d"), arg("params"), arg("xy").noconvert(), arg("ok").noconvert(), release,
       "Brown-distorted pinhole directions (any length; zero and non-finite invalid) -> pixels (the lens's PixelKernel).");

    m.def("cubemap_pixels", [](Vec d, Vec p, Out<double> xy, Out<bool> ok) {
        need(p.size() == 30, "cubemap: 30 parameters");
        cubemap_pixels(d.data(), points(d, 3, xy, 2, ok), p.data(), xy.data(), ok.data());
    }, arg("d"), arg("params"), arg("xy").noconvert(), arg("ok").noconvert(), release,
       "Cube map directions (any length; zero and non-finite invalid) -> pixels (the lens's PixelKernel).");

    m.def("eac_pixels", [](Vec d, Vec p, Out<double> xy, Out<bool> ok) {
        need(p.size() == 43, "eac: 43 parameters");
        const double* q = p.data();
        for (int k = 0; k < 6; ++k) {  // the components along A and B index d: 0, 1 or 2
            need(whole(q[7 + 6 * k + 2], 2) >= 0 && whole(q[7 + 6 * k + 4], 2) >= 0, "eac: a face's axes");
        }
        eac_pixels(d.data(), points(d, 3, xy, 2, ok), q, xy.data(), ok.data());
    }, arg("d"), arg("params"), arg("xy").noconvert(), arg("ok").noconvert(), release,
       "Equi-angular cube map directions (any length; zero and non-finite invalid) -> pixels (the lens's PixelKernel).");

    m.attr("pixel_kernel_ids") = [] {
        nb::dict ids;
        ids["equirect_pixels"] = 0;
        ids["perspective_pixels"] = 1;
        ids["hammer_pixels"] = 2;
        return ids;
    }();

    m.def("tiled_pixels", [](Vec d, Vec p, Out<double> xy, Out<bool> ok) {
        need(p.size() >= 1, "tiled: the number of tiles first");
        const double* q = p.data();
        const int64_t ntiles = whole(q[0], int64_t(p.size()));
        need(ntiles >= 0, "tiled: the number of tiles must be a whole number");
        size_t at = 1;
        for (int64_t k = 0; k < ntiles; ++k) {  // every tile's record inside p, with a known kernel
            static const double sizes[] = {9, 6, 4};  // the parameters of kernels 0, 1, 2
            need(at + 19 <= p.size() && whole(q[at], 2) >= 0 && pixel_fn(whole(q[at], 2)) != nullptr
                 && q[at + 1] == sizes[whole(q[at], 2)], "tiled: a tile's record");
            at += 19 + size_t(q[at + 1]);
        }
        need(at == p.size(), "tiled: the records do not fill the parameters");
        tiled_pixels(d.data(), points(d, 3, xy, 2, ok), q, xy.data(), ok.data());
    }, arg("d"), arg("params"), arg("xy").noconvert(), arg("ok").noconvert(), release,
       "Tiled grid: directions (any length) -> the pixel of the first tile that sees each (its PixelKernel).");

    m.def("division_unbend", [](Vec uv, double k1, double k2, double hi, double f_hi, bool strict, bool pole, Vec table,
                                double step, double tol, double res_tol, double rel_ulps, int64_t max_iter,
                                Out<double> out, Out<bool> ok) {
        int64_t n = points(uv, 2, out, 2, ok);
        division_unbend(uv.data(), n, k1, k2, hi, f_hi, strict, pole, table_of(table, step),
                        {tol, res_tol, rel_ulps, max_iter}, out.data(), ok.data());
    }, arg("uv"), arg("k1"), arg("k2"), arg("hi"), arg("f_hi"), arg("strict"), arg("pole"), arg("table"), arg("step"),
       arg("tol"), arg("res_tol"), arg("rel_ulps"), arg("max_iter"), arg("out").noconvert(), arg("ok").noconvert(),
       release, "Division model, direction side: undistorted (u, v) -> image (u, v) (solved).");

    m.def("brown_bend", [](Vec uv, double k1, double k2, double hi, double rd_fold, Vec table, double step, double tol,
                           double res_tol, double rel_ulps, int64_t max_iter, Out<double> out, Out<bool> ok) {
        int64_t n = points(uv, 2, out, 2, ok);
        brown_bend(uv.data(), n, k1, k2, hi, rd_fold, table_of(table, step), {tol, res_tol, rel_ulps, max_iter},
                   out.data(), ok.data());
    }, arg("uv"), arg("k1"), arg("k2"), arg("hi"), arg("rd_fold"), arg("table"), arg("step"), arg("tol"),
       arg("res_tol"), arg("rel_ulps"), arg("max_iter"), arg("out").noconvert(), arg("ok").noconvert(), release,
       "Brown polynomial, pixel side: image (u, v) -> undistorted (u, v) (solved).");

    m.def("tan_fisheye_dir_to_uv", [](Vec d, double F, double hi, double psi_max, bool strict, Vec table, double step,
                                      double tol, double res_tol, double rel_ulps, int64_t max_iter, Out<double> out,
                                      Out<bool> ok) {
        int64_t n = points(d, 3, out, 2, ok);
        tan_fisheye_dir_to_uv(d.data(), n, F, hi, psi_max, strict, table_of(table, step),
                              {tol, res_tol, rel_ulps, max_iter}, out.data(), ok.data());
    }, arg("d"), arg("F"), arg("hi"), arg("psi_max"), arg("strict"), arg("table"), arg("step"), arg("tol"),
       arg("res_tol"), arg("rel_ulps"), arg("max_iter"), arg("out").noconvert(), arg("ok").noconvert(), release,
       "Tan-fold fisheye, direction side: unit direction -> (u, v) (solved).");

    m.def("distort_points", [](Vec x, Vec y, Vec a, Vec b, double p1, double p2, Vec s, bool tangential, double fold,
                               Out<double> xd, Out<double> yd, Out<bool> ok) {
        const size_t n = x.size();
        need(y.size() == n && xd.size() == n && yd.size() == n && ok.size() == n, "point counts differ");
        distort_points(x.data(), y.data(), int64_t(n), distortion_of(a, b, p1, p2, s, tangential, fold), xd.data(),
                       yd.data(), ok.data());
    }, arg("x"), arg("y"), arg("a"), arg("b"), arg("p1"), arg("p2"), arg("s"), arg("tangential"), arg("fold"),
       arg("xd").noconvert(), arg("yd").noconvert(), arg("ok").noconvert(), release,
       "OpenCV's distortion of points inside the fold (with a positive Jacobian when tangential).");

    m.def("calibrated_project", [](Vec d, int64_t kind, Vec q, Vec a, Vec b, double p1, double p2, Vec s, bool distort,
                                   bool tangential, double fold, double fx, double fy, double skew, double cx,
                                   double cy, double width, double height, double slack, Out<double> xy,
                                   Out<bool> ok) {
        int64_t n = points(d, 3, xy, 2, ok);
        const Q3 qq = q3(q);
        const Distortion dist = distortion_of(a, b, p1, p2, s, tangential, fold);
        calibrated_project(d.data(), n, kind, qq.v, distort ? &dist : nullptr, {fx, fy, skew, cx, cy},
                           {width, height, slack}, xy.data(), ok.data());
    }, arg("d"), arg("kind"), arg("q"), arg("a"), arg("b"), arg("p1"), arg("p2"), arg("s"), arg("distort"),
       arg("tangential"), arg("fold"), arg("fx"), arg("fy"), arg("skew"), arg("cx"), arg("cy"), arg("width"),
       arg("height"), arg("slack"), arg("xy").noconvert(), arg("ok").noconvert(), release,
       "Calibrated model: lenslab directions -> lenslab pixels (projection, distortion, intrinsics, image test).");

    m.def("calibrated_unproject", [](Vec xy, int64_t kind, Vec q, Vec a, Vec b, double p1, double p2, Vec s,
                                     bool distort, bool tangential, double fold, double hi, double f_hi, bool strict,
                                     Vec table, double step, double tol, double res_tol, double rel_ulps,
                                     int64_t max_iter, double tol_2d, int64_t max_iter_2d, double fx, double fy,
                                     double skew, double cx, double cy, Out<double> d, Out<bool> ok) {
        int64_t n = points(xy, 2, d, 3, ok);
        const Q3 qq = q3(q);
        const Distortion dist = distortion_of(a, b, p1, p2, s, tangential, fold);
        const Table t = distort ? table_of(table, step) : Table{nullptr, 0, 1.0};
        return calibrated_unproject(xy.data(), n, kind, qq.v, distort ? &dist : nullptr, hi, f_hi, strict, t,
                                    {tol, res_tol, rel_ulps, max_iter}, tol_2d, max_iter_2d, {fx, fy, skew, cx, cy},
                                    d.data(), ok.data());
    }, arg("xy"), arg("kind"), arg("q"), arg("a"), arg("b"), arg("p1"), arg("p2"), arg("s"), arg("distort"),
       arg("tangential"), arg("fold"), arg("hi"), arg("f_hi"), arg("strict"), arg("table"), arg("step"), arg("tol"),
       arg("res_tol"), arg("rel_ulps"), arg("max_iter"), arg("tol_2d"), arg("max_iter_2d"), arg("fx"), arg("fy"),
       arg("skew"), arg("cx"), arg("cy"), arg("d").noconvert(), arg("ok").noconvert(), release,
       "Calibrated model: lenslab pixels -> unit directions (undistortion solved); the largest iteration count.");

    m.def("ocam_project", [](Vec d, Vec pol_unit, double hi, double a_hi, bool strict, Vec table, double step,
                             double tol, double res_tol, double rel_ulps, int64_t max_iter, double c, double dd,
                             double e, double xc, double yc, double width, double height, double slack,
                             Out<double> xy, Out<bool> ok) {
        int64_t n = points(d, 3, xy, 2, ok);
        return ocam_project(d.data(), n, pol_unit.data(), int64_t(pol_unit.size()), hi, a_hi, strict,
                            table_of(table, step), {tol, res_tol, rel_ulps, max_iter}, c, dd, e, xc, yc,
                            {width, height, slack}, xy.data(), ok.data());
    }, arg("d"), arg("pol_unit"), arg("hi"), arg("a_hi"), arg("strict"), arg("table"), arg("step"), arg("tol"),
       arg("res_tol"), arg("rel_ulps"), arg("max_iter"), arg("c"), arg("d_"), arg("e"), arg("xc"), arg("yc"),
       arg("width"), arg("height"), arg("slack"), arg("xy").noconvert(), arg("ok").noconvert(), release,
       "OCamCalib: lenslab directions -> lenslab pixels (the radius solved); the largest iteration count.");

    m.def("lensfun_dir_to_pixel", [](Vec d, int64_t kind, double f, Vec coeffs, double r_lim, double cx, double cy,
                                     double norm, Out<double> xy, Out<bool> ok) {
        int64_t n = points(d, 3, xy, 2, ok);
        need(coeffs.size() >= 1, "coeffs: one term or more");
        lensfun_dir_to_pixel(d.data(), n, kind, f, coeffs.data(), int64_t(coeffs.size()), r_lim, cx, cy, norm,
                             xy.data(), ok.data());
    }, arg("d"), arg("kind"), arg("f"), arg("coeffs"), arg("r_lim"), arg("cx"), arg("cy"), arg("norm"),
       arg("xy").noconvert(), arg("ok").noconvert(), release,
       "lensfun profile: directions -> pixels (projection, distortion P(r), pixel frame), unbounded by the image.");
}
