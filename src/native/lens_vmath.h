// Four-wide transcendental functions for the lens kernels (lens_dirs.cpp, lens_pixels.cpp, lens_cubemap.cpp):
// glibc's vector maths (libmvec, within 4 ulps of libm; CMakeLists.txt finds it and defines LENSLAB_MVEC) where
// the kernels are built for AVX2, the scalar libm calls otherwise. Each lane is its own: an element's value does
// not depend on its neighbours or on its place in a call.
#pragma once

#include <cmath>

#ifdef LENSLAB_MVEC
#include <immintrin.h>
extern "C" __m256d _ZGVdN4vv_atan2(__m256d, __m256d);
extern "C" __m256d _ZGVdN4v_acos(__m256d);
extern "C" __m256d _ZGVdN4v_sin(__m256d);
extern "C" __m256d _ZGVdN4v_cos(__m256d);
extern "C" __m256d _ZGVdN4v_log(__m256d);
extern "C" __m256d _ZGVdN4v_tanh(__m256d);
extern "C" __m256d _ZGVdN4v_cosh(__m256d);
#endif

namespace lenslab::lens::vmath {

// atan2(y[j], x[j]) of four pairs, into out
inline void atan2_4(double* out, const double* y, const double* x) {
#ifdef LENSLAB_MVEC
    _mm256_storeu_pd(out, _ZGVdN4vv_atan2(_mm256_loadu_pd(y), _mm256_loadu_pd(x)));
#else
    for (int j = 0; j < 4; ++j) out[j] = std::atan2(y[j], x[j]);
#endif
}

// arc cosine of four values, into out (the map lattice's field test, lattice.cpp)
inline void acos4(double* out, const double* a) {
#ifdef LENSLAB_MVEC
    _mm256_storeu_pd(out, _ZGVdN4v_acos(_mm256_loadu_pd(a)));
#else
    for (int j = 0; j < 4; ++j) out[j] = std::acos(a[j]);
#endif
}

// sin and cos of four angles, into sn and cs
inline void sin_cos4(const double* a, double* sn, double* cs) {
#ifdef LENSLAB_MVEC
    const __m256d v = _mm256_loadu_pd(a);
    _mm256_storeu_pd(sn, _ZGVdN4v_sin(v));
    _mm256_storeu_pd(cs, _ZGVdN4v_cos(v));
#else
    for (int j = 0; j < 4; ++j) {
        sn[j] = std::sin(a[j]);
        cs[j] = std::cos(a[j]);
    }
#endif
}

// log of four values, written over them
inline void log4(double* a) {
#ifdef LENSLAB_MVEC
    _mm256_storeu_pd(a, _ZGVdN4v_log(_mm256_loadu_pd(a)));
#else
    for (int j = 0; j < 4; ++j) a[j] = std::log(a[j]);
#endif
}

// tanh and cosh of four values, into th and ch
inline void tanh_cosh4(const double* a, double* th, double* ch) {
#ifdef LENSLAB_MVEC
    const __m256d v = _mm256_loadu_pd(a);
    _mm256_storeu_pd(th, _ZGVdN4v_tanh(v));
    _mm256_storeu_pd(ch, _ZGVdN4v_cosh(v));
#else
    for (int j = 0; j < 4; ++j) {
        th[j] = std::tanh(a[j]);
        ch[j] = std::cosh(a[j]);
    }
#endif
}

}  // namespace lenslab::lens::vmath
