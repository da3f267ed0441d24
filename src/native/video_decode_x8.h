// Part of video_ycbcr.cpp (included inside its anonymous namespace, after lookup): the decoding pass's 8-bit rows
// eight pixels at a time with AVX2 gathers, the same arithmetic as its scalar loop.
#pragma once

// Row pixels c0 to c1 - 1 of 8-bit planes, eight at a time, as to_linear's scalar loop over R' and B' tables computes
// them: R' and B' read from `tr` and `tb` (rb_tables), G' the curve `t` at LY[Y'] + g[chroma sample] (clamped, its
// pair interpolated by one fused multiply-add), written interleaved to `o` (the row's pixel 0). `yr`, `ur`, `vr`: the
// row's samples; `g`: G''s chroma term by chroma sample (index c >> hx). Returns the first pixel it did not do (c0
// without AVX2); it stops where a group would read chroma at or past `k1`.
inline int64_t rgb8_row_x8(const uint8_t* yr, const uint8_t* ur, const uint8_t* vr, int hx, const float* g,
                           const float* LY, const float* t, const float* tr, const float* tb, int64_t c0, int64_t c1,
                           int64_t k1, float* o) {
#if defined(__AVX2__) && defined(__FMA__)
    // lane l's chroma sample, counted from the group's first (c >> hx): ((c & odd) + l) >> hx, c's parity fixed
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256i rep = _mm256_srli_epi32(_mm256_add_epi32(lane, _mm256_set1_epi32(int32_t(c0 & hx))), hx);
    const __m256 zero = _mm256_setzero_ps(), top = _mm256_set1_ps(65535.0f);
    // interleaving: out k = blend(blend(R permuted, G permuted, gm), B permuted, bm)
    const __m256i ir0 = _mm256_setr_epi32(0, 0, 0, 1, 0, 0, 2, 0), ig0 = _mm256_setr_epi32(0, 0, 0, 0, 1, 0, 0, 2),
                  ib0 = _mm256_setr_epi32(0, 0, 0, 0, 0, 1, 0, 0);
    const __m256i ir1 = _mm256_setr_epi32(0, 3, 0, 0, 4, 0, 0, 5), ig1 = _mm256_setr_epi32(0, 0, 3, 0, 0, 4, 0, 0),
                  ib1 = _mm256_setr_epi32(2, 0, 0, 3, 0, 0, 4, 0);
    const __m256i ir2 = _mm256_setr_epi32(0, 0, 6, 0, 0, 7, 0, 0), ig2 = _mm256_setr_epi32(5, 0, 0, 6, 0, 0, 7, 0),
                  ib2 = _mm256_setr_epi32(0, 5, 0, 0, 6, 0, 0, 7);
    int64_t c = c0;
    for (; c + 8 <= c1 && (c >> hx) + 8 <= k1; c += 8) {
        const int64_t cc = c >> hx;
        const __m256i y = _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(yr + c)));
        const __m256i u = _mm256_permutevar8x32_epi32(
            _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(ur + cc))), rep);
        const __m256i v = _mm256_permutevar8x32_epi32(
            _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(vr + cc))), rep);
        const __m256 R = _mm256_i32gather_ps(tr, _mm256_add_epi32(_mm256_slli_epi32(v, 8), y), 4);
        const __m256 B = _mm256_i32gather_ps(tb, _mm256_add_epi32(_mm256_slli_epi32(u, 8), y), 4);
        __m256 x = _mm256_add_ps(_mm256_i32gather_ps(LY, y, 4), _mm256_permutevar8x32_ps(_mm256_loadu_ps(g + cc), rep));
        x = _mm256_min_ps(_mm256_max_ps(x, zero), top);  // as lookup: x > 0 ? min(x, 65535) : 0
        const __m256i i = _mm256_cvttps_epi32(x), i2 = _mm256_add_epi32(i, i);
        const __m256 f = _mm256_sub_ps(x, _mm256_cvtepi32_ps(i));
        const __m256 G = _mm256_fmadd_ps(f, _mm256_i32gather_ps(t + 1, i2, 4), _mm256_i32gather_ps(t, i2, 4));
        float* d = o + 3 * c;
        _mm256_storeu_ps(d, _mm256_blend_ps(_mm256_blend_ps(_mm256_permutevar8x32_ps(R, ir0),
                                                            _mm256_permutevar8x32_ps(G, ig0), 0x92),
                                            _mm256_permutevar8x32_ps(B, ib0), 0x24));
        _mm256_storeu_ps(d + 8, _mm256_blend_ps(_mm256_blend_ps(_mm256_permutevar8x32_ps(R, ir1),
                                                                _mm256_permutevar8x32_ps(G, ig1), 0x24),
                                                _mm256_permutevar8x32_ps(B, ib1), 0x49));
        _mm256_storeu_ps(d + 16, _mm256_blend_ps(_mm256_blend_ps(_mm256_permutevar8x32_ps(R, ir2),
                                                                 _mm256_permutevar8x32_ps(G, ig2), 0x49),
                                                 _mm256_permutevar8x32_ps(B, ib2), 0x92));
    }
    return c;
#else
    (void)yr; (void)ur; (void)vr; (void)hx; (void)g; (void)LY; (void)t; (void)tr; (void)tb; (void)c1; (void)k1;
    (void)o;
    return c0;
#endif
}
