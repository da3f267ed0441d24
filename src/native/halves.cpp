// float32 -> float16 for every half-float writer, EXR and TIFF (lenslab.io.halves.to_half, registered by
// register_halves): one pass, finite values beyond half's range clamped to +-65504 (and counted), infinities kept,
// NaN as NumPy's cast makes it.
// The output may be the input's own memory (half i at byte 2i, float i at byte 4i): written in order on one
// thread, a store never reaches a float not yet read. NumPy reference: lenslab.io.halves.to_half_reference.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cstdint>
#include <cstring>
#if defined(__F16C__) && defined(__AVX__)
#include <immintrin.h>
#endif

#include "bind.h"

namespace nb = nanobind;

namespace {

constexpr float HALF_MAX = 65504.0f;

// NumPy's float32 -> float16 bits (round to nearest even; NaN keeps the top of its payload, never becoming inf)
uint16_t half_bits(uint32_t f) {
    const uint16_t sign = uint16_t((f & 0x80000000u) >> 16);
    const uint32_t exp = f & 0x7f800000u;
    if (exp >= 0x47800000u) {  // Inf, NaN or overflow (the caller has clamped the finite ones)
        const uint32_t sig = f & 0x007fffffu;
        if (exp == 0x7f800000u && sig != 0) {
            uint16_t r = uint16_t(0x7c00u + (sig >> 13));
            return uint16_t(sign + (r == 0x7c00u ? r + 1 : r));
        }
        return uint16_t(sign + 0x7c00u);
    }
    if (exp <= 0x38000000u) {  // a subnormal half or zero: the 24-bit significand times 2^(e - 126) half units
        if (exp < 0x33000000u) return sign;  // below half the smallest subnormal: zero
        const uint32_t shift = 126u - (exp >> 23), sig = 0x00800000u + (f & 0x007fffffu);
        uint32_t h = sig >> shift;
        const uint32_t rest = sig & ((1u << shift) - 1u), tie = 1u << (shift - 1u);
        if (rest > tie || (rest == tie && (h & 1u))) ++h;  // ties to even (may become the smallest normal)
        return uint16_t(sign + h);
    }
    uint32_t h = ((exp - 0x38000000u) >> 13) + ((f & 0x007fffffu) >> 13);
    uint32_t rest = f & 0x1fffu;
    if (rest > 0x1000u || (rest == 0x1000u && (h & 1u))) ++h;  // may carry into the exponent: still right
    return uint16_t(sign + h);
}

uint16_t clamped_bits(float v, int64_t& count) {
    if (v > HALF_MAX && v <= 3.4028235e38f) { v = HALF_MAX; ++count; }
    else if (v < -HALF_MAX && v >= -3.4028235e38f) { v = -HALF_MAX; ++count; }
    uint32_t f;
    std::memcpy(&f, &v, sizeof f);
    return half_bits(f);
}

int64_t to_half(const float* src, uint16_t* dst, int64_t n) {
    int64_t count = 0, i = 0;
#if defined(__F16C__) && defined(__AVX__)
    const __m256 hi = _mm256_set1_ps(HALF_MAX);
    for (; i + 8 <= n; i += 8) {
        __m256 v = _mm256_loadu_ps(src + i);
        const __m256 a = _mm256_andnot_ps(_mm256_set1_ps(-0.0f), v);
        // NaN, or a magnitude past half's largest (finite or not): the scalar steps, NumPy's bits
        if (_mm256_movemask_ps(_mm256_cmp_ps(a, hi, _CMP_NLE_UQ)) != 0) {
            uint16_t h[8];
            float f[8];
            _mm256_storeu_ps(f, v);
            for (int k = 0; k < 8; ++k) h[k] = clamped_bits(f[k], count);
            std::memcpy(dst + i, h, sizeof h);
            continue;
        }
        _mm_storeu_si128(reinterpret_cast<__m128i*>(dst + i), _mm256_cvtps_ph(v, _MM_FROUND_TO_NEAREST_INT));
    }
#endif
    for (; i < n; ++i) dst[i] = clamped_bits(src[i], count);
    return count;
}

}  // namespace

void register_halves(nb::module_& m) {
    using lenslab::bind::In;
    using lenslab::bind::need;
    using lenslab::bind::Out;
    m.def("to_half", [](In<float> src, Out<uint16_t> dst) {
        need(src.ndim() == 1 && dst.ndim() == 1 && dst.shape(0) == src.shape(0), "src and dst: n values each");
        const auto* s = reinterpret_cast<const char*>(src.data());
        const auto* d = reinterpret_cast<const char*>(dst.data());
        const int64_t n = int64_t(src.shape(0));
        // the output may be the input's own memory only as its first half (it trails the reading)
        need(d + 2 * n <= s || s + 4 * n <= d || d == s, "dst overlaps src other than at its start");
        return to_half(src.data(), dst.data(), n);
    }, nb::arg("src"), nb::arg("dst").noconvert(), nb::call_guard<nb::gil_scoped_release>());
}
