// The per-channel kernels of two RGB tone curves (lenslab.tone.agx, lenslab.tone.pbr_neutral): one pass
// over interleaved float32 RGB pixels, where NumPy takes some twenty passes over a planar copy. Each returns
// the largest bit pattern of the pixels it read: at or above 0x7F800000 (+inf) the block held a NaN, an
// infinity or a negative value, and the caller repairs a copy and runs the kernel again (lenslab.tone.sweep).
//
// Pixels go through in chunks of CHUNK, split into planes on the stack, so that every loop is a plain loop
// over contiguous values that the compiler vectorises. This file is compiled without fused multiply-adds
// (CMakeLists.txt): the PBR Neutral kernel runs the float32 steps of its NumPy reference in the same order and
// gives the same bits. AgX is in tone_agx.cpp.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "bind.h"
#include "tone.h"

namespace nb = nanobind;
using namespace lenslab;
using lenslab::bind::In;
using lenslab::bind::Out;

namespace {

constexpr int64_t CHUNK = TONE_CHUNK;

// PBR Neutral's constants, float32 as the NumPy kernel rounds them (lenslab.tone.pbr_neutral).
struct Pbr { float scale, big, toe_end, toe_slope, ks, d_minus_ks, minus_d2, kd; };

// Khronos PBR Neutral on n interleaved pixels: the float32 steps of lenslab.tone.pbr_neutral's NumPy kernel,
// in its order, so the bits are the same.
uint32_t pbr_pixels(const float* src, float* dst, int64_t n, Pbr k) {
    alignas(64) float x0[CHUNK], x1[CHUNK], x2[CHUNK];
    const uint32_t* bits = reinterpret_cast<const uint32_t*>(src);
    uint32_t worst = 0;
    const bool exposed = k.scale != 1.0f;
    for (int64_t s = 0; s < n; s += CHUNK) {
        const int64_t m = std::min(CHUNK, n - s);
        const float* p = src + 3 * s;
        const uint32_t* q = bits + 3 * s;
        for (int64_t i = 0; i < 3 * m; ++i) worst = greater(worst, q[i]);
        for (int64_t i = 0; i < m; ++i) {
            x0[i] = p[3 * i];
            x1[i] = p[3 * i + 1];
            x2[i] = p[3 * i + 2];
        }
        if (exposed)
            for (int64_t i = 0; i < m; ++i) {
                x0[i] = clamp(x0[i] * k.scale, 0.0f, k.big);
                x1[i] = clamp(x1[i] * k.scale, 0.0f, k.big);
                x2[i] = clamp(x2[i] * k.scale, 0.0f, k.big);
            }
        for (int64_t i = 0; i < m; ++i) {
            float low = clamp(lesser(lesser(x0[i], x1[i]), x2[i]), 0.0f, k.toe_end);
            low = low * (low * k.toe_slope + 1.0f);
            float d0 = x0[i] - low, d1 = x1[i] - low, d2 = x2[i] - low;
            const float peak = clamp(greater(greater(d0, d1), d2), k.ks, k.big);
            const float new_peak = k.minus_d2 / (peak + k.d_minus_ks) + 1.0f;
            float h = 1.0f / ((peak - new_peak) * k.kd + 1.0f);
            const float ratio = new_peak / peak * h;
            h = (1.0f - h) * new_peak;
            x0[i] = clamp(d0 * ratio + h, 0.0f, 1.0f);
            x1[i] = clamp(d1 * ratio + h, 0.0f, 1.0f);
            x2[i] = clamp(d2 * ratio + h, 0.0f, 1.0f);
        }
        float* o = dst + 3 * s;
        for (int64_t i = 0; i < m; ++i) {
            o[3 * i] = x0[i];
            o[3 * i + 1] = x1[i];
            o[3 * i + 2] = x2[i];
        }
    }
    return worst;
}

void same_pixels(size_t a, size_t b) {
    if (a != b || a % 3) throw std::invalid_argument("src and dst must hold the same whole RGB pixels");
}

}  // namespace

void register_tone(nb::module_& m) {
    m.def("agx_pixels", [](In<float> src, Out<float> dst, In<double> m_in, In<double> m_out, In<double> poly,
                           double top, double floor_, double power) {
        same_pixels(src.size(), dst.size());
        if (m_in.size() != 9 || m_out.size() != 9 || poly.size() != 7)
            throw std::invalid_argument("agx takes 3 x 3 matrices and 7 coefficients");
        // the kernel's power is 2.2 (tone_agx.cpp); floor^2.2 must be a normal float32
        if (!(top >= 1.0 && top < 1e30 && floor_ >= std::ldexp(1.0, -57) && floor_ < 1.0 && power == 2.2))
            throw std::invalid_argument("agx constants out of range");
        return agx_pixels(src.data(), dst.data(), int64_t(src.size() / 3), m_in.data(), m_out.data(), poly.data(), top, floor_, power);
    }, nb::arg("src"), nb::arg("dst").noconvert(), nb::arg("m_in"), nb::arg("m_out"), nb::arg("poly"), nb::arg("top"),
       nb::arg("floor"), nb::arg("power"), nb::call_guard<nb::gil_scoped_release>(),
       "AgX on interleaved float32 RGB pixels; returns the largest bit pattern read.");

    m.def("pbr_neutral_pixels", [](In<float> src, Out<float> dst, In<float> c) {
        same_pixels(src.size(), dst.size());
        if (c.size() != 8) throw std::invalid_argument("pbr-neutral takes 8 constants");
        const float* v = c.data();
        return pbr_pixels(src.data(), dst.data(), int64_t(src.size() / 3), {v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]});
    }, nb::arg("src"), nb::arg("dst").noconvert(), nb::arg("constants"), nb::call_guard<nb::gil_scoped_release>(),
       "Khronos PBR Neutral on interleaved float32 RGB pixels; returns the largest bit pattern read.");
}
