// Part of video_ycbcr.cpp (included inside its anonymous namespace, after Range): the encoding pass's rows eight
// pixels at a time with AVX2, the same arithmetic as its scalar loop.
#pragma once

// The pixels of a row of linear float32 (cols x 3) from the first on, eight at a time, as the scalar loop of
// from_linear_t computes them: R'G'B' by the curve (none: the values themselves) clamped to [0, 1], Y' in float64
// rounded to its code in `yr`, E'cb and E'cr in float64 in `u`, `v`. Returns how many pixels it did (a multiple of 8;
// 0 without AVX2).
template <typename T>
int64_t row_codes_x8(const float* a, int64_t cols, const Curve& curve, const double* k, const Range& r, double top,
                     T* yr, double* u, double* v) {
#if defined(__AVX2__) && defined(__FMA__)
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
    // gather each channel's eight values from three vectors of interleaved R, G, B
    const __m256i pr0 = _mm256_setr_epi32(0, 3, 6, 0, 0, 0, 0, 0), pr1 = _mm256_setr_epi32(0, 0, 0, 1, 4, 7, 0, 0),
                  pr2 = _mm256_setr_epi32(0, 0, 0, 0, 0, 0, 2, 5);
    const __m256i pg0 = _mm256_setr_epi32(1, 4, 7, 0, 0, 0, 0, 0), pg1 = _mm256_setr_epi32(0, 0, 0, 2, 5, 0, 0, 0),
                  pg2 = _mm256_setr_epi32(0, 0, 0, 0, 0, 0, 3, 6);
    const __m256i pb0 = _mm256_setr_epi32(2, 5, 0, 0, 0, 0, 0, 0), pb1 = _mm256_setr_epi32(0, 0, 0, 3, 6, 0, 0, 0),
                  pb2 = _mm256_setr_epi32(0, 0, 0, 0, 0, 1, 4, 7);
    const __m256d K[9] = {_mm256_set1_pd(k[0]), _mm256_set1_pd(k[1]), _mm256_set1_pd(k[2]), _mm256_set1_pd(k[3]),
                          _mm256_set1_pd(k[4]), _mm256_set1_pd(k[5]), _mm256_set1_pd(k[6]), _mm256_set1_pd(k[7]),
                          _mm256_set1_pd(k[8])};
    const __m256d ys = _mm256_set1_pd(r.ys), y0 = _mm256_set1_pd(r.y0), dtop = _mm256_set1_pd(top),
                  dzero = _mm256_setzero_pd();
    // eight pixels from x: codes to yr, E'cb and E'cr to u and v
    auto group = [&](const float* x, T* yr, double* u, double* v) {
        alignas(32) float e[24];
        if (curve.table != nullptr) {
            lenslab_video::curve_many(curve, x, e, 24);
        } else {
            std::memcpy(e, x, sizeof e);
        }
        __m256 w[3];
        for (int q = 0; q < 3; ++q)  // max first: NaN -> 0
            w[q] = _mm256_min_ps(_mm256_max_ps(_mm256_load_ps(e + 8 * q), zero), one);
        __m256 R = _mm256_blend_ps(_mm256_blend_ps(_mm256_permutevar8x32_ps(w[0], pr0),
                                                   _mm256_permutevar8x32_ps(w[1], pr1), 0x38),
                                   _mm256_permutevar8x32_ps(w[2], pr2), 0xC0);
        __m256 G = _mm256_blend_ps(_mm256_blend_ps(_mm256_permutevar8x32_ps(w[0], pg0),
                                                   _mm256_permutevar8x32_ps(w[1], pg1), 0x18),
                                   _mm256_permutevar8x32_ps(w[2], pg2), 0xE0);
        __m256 B = _mm256_blend_ps(_mm256_blend_ps(_mm256_permutevar8x32_ps(w[0], pb0),
                                                   _mm256_permutevar8x32_ps(w[1], pb1), 0x1C),
                                   _mm256_permutevar8x32_ps(w[2], pb2), 0xE0);
        __m128i codes[2];
        for (int h = 0; h < 2; ++h) {
            __m256d e0 = _mm256_cvtps_pd(h ? _mm256_extractf128_ps(R, 1) : _mm256_castps256_ps128(R));
            __m256d e1 = _mm256_cvtps_pd(h ? _mm256_extractf128_ps(G, 1) : _mm256_castps256_ps128(G));
            __m256d e2 = _mm256_cvtps_pd(h ? _mm256_extractf128_ps(B, 1) : _mm256_castps256_ps128(B));
            __m256d wy = _mm256_fmadd_pd(K[2], e2, _mm256_fmadd_pd(K[1], e1, _mm256_mul_pd(K[0], e0)));
            __m256d wu = _mm256_fmadd_pd(K[5], e2, _mm256_fmadd_pd(K[4], e1, _mm256_mul_pd(K[3], e0)));
            __m256d wv = _mm256_fmadd_pd(K[8], e2, _mm256_fmadd_pd(K[7], e1, _mm256_mul_pd(K[6], e0)));
            _mm256_storeu_pd(u + 4 * h, wu);
            _mm256_storeu_pd(v + 4 * h, wv);
            __m256d y = _mm256_fmadd_pd(wy, ys, y0);
            y = _mm256_min_pd(_mm256_max_pd(y, dzero), dtop);
            codes[h] = _mm256_cvtpd_epi32(_mm256_round_pd(y, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC));
        }
        __m128i c16 = _mm_packus_epi32(codes[0], codes[1]);  // eight codes, at most `top` < 2^16
        if constexpr (sizeof(T) == 1) {
            _mm_storel_epi64(reinterpret_cast<__m128i*>(yr), _mm_packus_epi16(c16, c16));
        } else {
            _mm_storeu_si128(reinterpret_cast<__m128i*>(yr), c16);
        }
    };
    // eight black pixels (every bit 0: outside a lens's view, where a warp leaves its output at 0) give the same
    // codes wherever they are: computed once by `group` itself, then copied (the same bits)
    alignas(32) static const float zeros[24] = {};
    T black_y[8];
    double black_u[8], black_v[8];
    group(zeros, black_y, black_u, black_v);
    int64_t c = 0;
    for (; c + 8 <= cols; c += 8) {
        const float* x = a + 3 * c;
        const __m256i any = _mm256_or_si256(
            _mm256_or_si256(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(x)),
                            _mm256_loadu_si256(reinterpret_cast<const __m256i*>(x + 8))),
            _mm256_loadu_si256(reinterpret_cast<const __m256i*>(x + 16)));
        if (_mm256_testz_si256(any, any)) {
            std::memcpy(yr + c, black_y, sizeof black_y);
            std::memcpy(u + c, black_u, sizeof black_u);
            std::memcpy(v + c, black_v, sizeof black_v);
        } else {
            group(x, yr + c, u + c, v + c);
        }
    }
    return c;
#else
    (void)a; (void)cols; (void)curve; (void)k; (void)r; (void)top; (void)yr; (void)u; (void)v;
    return 0;
#endif
}
