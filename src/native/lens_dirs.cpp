// Pixel -> direction of the lens models with a closed form (their DirKernel, lenslab.lenses.core.protocol), and
// the bindings, registered into lenslab.cxx_kernels by register_lens_dirs(). The same operations in the same order
// as the models' NumPy steps (Lens.pixel_to_dir: pixel_to_uv, the model's uv_to_dir, the finiteness tests and
// clean), so a warp's exact map costs a fraction of the NumPy one; NumPy references in
// lenslab/lenses/formulas/reference.py (fisheye_dirs), held to them by tests/lenses/test_native_pixel_dirs.py.
// Built with every multiply and add rounded as written (CMakeLists.txt), as the NumPy code rounds them.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "lens_formulas.h"

namespace nb = nanobind;

namespace lenslab::lens {

namespace {

inline bool finite(double v) { return std::isfinite(v); }

// max(t, 0) as np.maximum takes it (a NaN stays NaN)
inline double at_least0(double t) { return t < 0.0 ? 0.0 : t; }

// One pixel of a fisheye (lenslab.lenses.projections.fisheye.Fisheye.uv_to_dir through Lens.pixel_to_dir).
// p = W, H, H / W, kind, plane scale, s_max^2 (with the rim slack), cx, cy, r_ref, local (0: the image centre
// and r_ref = 1, no shift)
template <int64_t KIND>
inline void fisheye_one(double x, double y, const double* p, double* d, bool* ok) {
    const double w = p[0], h = p[1], aspect = p[2], c = p[4], s_max2 = p[5];
    double u = x * 2.0;  // Lens.pixel_to_uv, in its order
    u /= w;
    u -= 1.0;
    double v = y * 2.0;
    v /= h;
    v = 1.0 - v;
    if (w != h) v *= aspect;
    if (p[9] != 0.0) {  // Fisheye._to_local
        u -= p[6];
        v -= p[7];
        u /= p[8];
        v /= p[8];
    }
    const double px = u * c, py = v * c;  // azimuthal.plane_to_dir
    const double s2 = px * px + py * py;
    double k, dz;
    if constexpr (KIND == EQUIDISTANT) {
        const double s = std::sqrt(s2);
        k = s > 0.0 ? std::sin(s) / s : 1.0;
        dz = std::cos(s);
    } else if constexpr (KIND == EQUISOLID) {
        const double q = 0.25 * s2;
        k = std::sqrt(at_least0(1.0 - q));
        dz = q * -2.0;
        dz += 1.0;
    } else if constexpr (KIND == STEREOGRAPHIC) {
        const double q2 = 0.25 * s2;
        k = 1.0 / (1.0 + q2);
        dz = k * (1.0 - q2);
    } else {  // ORTHOGRAPHIC
        k = 1.0;
        dz = std::sqrt(at_least0(1.0 - s2));
    }
    const double dx = px * k, dy = py * k;
    const double r2 = u * u + v * v;
    bool good = r2 <= s_max2;
    good = good && finite(x * x + y * y);  // Lens.pixel_to_dir: a non-finite pixel has no ray
    good = good && finite(dx * dx + dy * dy + dz * dz);  // clean()
    *ok = good;
    d[0] = good ? dx : 0.0;
    d[1] = good ? dy : 0.0;
    d[2] = good ? dz : 0.0;
}

template <int64_t KIND>
void fisheye_loop(const double* xy, int64_t n, const double* p, double* d, bool* ok) {
    for (int64_t i = 0; i < n; ++i) fisheye_one<KIND>(xy[2 * i], xy[2 * i + 1], p, d + 3 * i, ok + i);
}

}  // namespace

// fisheye pixels -> unit directions (0 and false where the lens has no ray)
void fisheye_dirs(const double* xy, int64_t n, const double* p, double* d, bool* ok) {
    switch (int64_t(p[3])) {
        case EQUIDISTANT: fisheye_loop<EQUIDISTANT>(xy, n, p, d, ok); break;
        case EQUISOLID: fisheye_loop<EQUISOLID>(xy, n, p, d, ok); break;
        case STEREOGRAPHIC: fisheye_loop<STEREOGRAPHIC>(xy, n, p, d, ok); break;
        case ORTHOGRAPHIC: fisheye_loop<ORTHOGRAPHIC>(xy, n, p, d, ok); break;
        default: throw std::invalid_argument("fisheye_dirs: not a fisheye mapping code");
    }
}

}  // namespace lenslab::lens

namespace {

template <typename T> using In = nb::ndarray<const T, nb::c_contig, nb::device::cpu>;
template <typename T> using Out = nb::ndarray<T, nb::c_contig, nb::device::cpu>;

void need(bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(what);
}

}  // namespace

void register_lens_dirs(nb::module_& m) {
    m.def("fisheye_dirs", [](In<double> xy, In<double> p, Out<double> d, Out<bool> ok) {
        need(xy.size() % 2 == 0, "pixels must be rows of (x, y)");
        const size_t n = xy.size() / 2;
        need(d.size() == 3 * n && ok.size() == n, "outputs must hold one row per pixel");
        need(p.size() == 10, "fisheye_dirs: 10 parameters");
        lenslab::lens::fisheye_dirs(xy.data(), int64_t(n), p.data(), d.data(), ok.data());
    }, nb::arg("xy"), nb::arg("params"), nb::arg("d").noconvert(), nb::arg("ok").noconvert(),
       nb::call_guard<nb::gil_scoped_release>(),
       "Fisheye pixels (any length; non-finite ones invalid) -> unit directions (the lens's DirKernel).");
}
