// The path tracer's bounce loop for Lambertian scenes lit by area lights (tracer.wavefront): the passes of
// lenslab.cxx_kernels.LambertScene, bound in tracer_paths.cpp. Per bounce Python makes three calls: `intersect`
// (the closest hits, in embree packets), `shade` (emission with its MIS weight, a light sample and its shadow ray,
// the cosine-weighted continuation, Russian roulette) and `settle` (one rtcOccluded1 per shadow ray, the visible
// light added, finished paths written out, the rest moved up). Each is the NumPy step of tracer.integrators (the
// reference, FUSED = False) per path, in the same float32 operations in the same order. Include this header only
// from a file built with -ffp-contract=off (no fused multiply-adds; see CMakeLists.txt): then every path's radiance
// is the NumPy steps' bit for bit. Embree's entry points come in as addresses from the library that embreex ships
// (tracer.embree_api): no embree headers or link-time dependency.
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "bind.h"

namespace lenslab_tracer {

namespace nb = nanobind;

using lenslab::bind::In;
using lenslab::bind::Out;
using lenslab::bind::need;

// Python's max and min (as numba compiles them): the first argument unless the second compares greater/less
inline float pmax(float a, float b) { return b > a ? b : a; }
inline float pmin(float a, float b) { return b < a ? b : a; }

// float32 constants rounded from the float64 values, as np.float32(...) makes them in the NumPy steps
constexpr float zero = 0.0f, one = 1.0f, two = 2.0f;
constexpr float tiny = float(1e-12), inv_pi = float(1.0 / 3.141592653589793);
constexpr float shrink = float(1.0 - 1e-4), short_ = float(1e-6);
constexpr float far_ = float(1e37);  // the reach of an unbounded ray, as embreex gives it
constexpr uint32_t INVALID = 0xFFFFFFFFu;

// RTCRayHitK of embree 4 (one instance level): a packet of K rays, structure of arrays: org, tnear, dir, time,
// tfar, mask, id, flags, then Ng, u, v, primID, geomID, instID (and instPrimID where embree has it built in),
// 64-byte aligned. Closest-hit packets give the same hits and distances, bit for bit, as one ray at a time
// (rtcIntersect1, which embreex casts): the same triangle test per ray, run in SIMD lanes (tests compare them
// with embreex on rays that leave surfaces and rays aimed at shared edges and corners). Occlusion packets do
// not (a few rays in 10^4 that graze an edge come out the other way), so shadow rays go one at a time.
#if defined(__AVX512F__)
constexpr int K = 16;  // embree's widest packets, as wide as the CPU's vectors (-march=native)
#else
constexpr int K = 8;
#endif
struct alignas(64) RayHitK {
    float org[3][K], tnear[K], dir[3][K], time[K], tfar[K];
    uint32_t mask[K], id[K], flags[K];
    float Ng[3][K], u[K], v[K];
    uint32_t primID[K], geomID[K], instID[K], instPrimID[K];

    // lane l: a ray from o along d up to tfar (the rest of the packet's lanes stay as they were)
    void set(int l, const float* o, const float* d, float reach) {
        for (int c = 0; c < 3; ++c) org[c][l] = o[c], dir[c][l] = d[c];
        tnear[l] = zero, time[l] = zero, tfar[l] = reach;
        mask[l] = INVALID, id[l] = 0, flags[l] = 0;
        primID[l] = INVALID, geomID[l] = INVALID, instID[l] = INVALID;
    }
};
using CastK = void (*)(const int* valid, void* scene, void* rays, void* args);

// RTCRay of embree 4, one ray (16-byte aligned): all an occlusion query reads and writes
struct alignas(16) RayHit1 {
    float org[3], tnear, dir[3], time, tfar;
    uint32_t mask, id, flags;
    void set(const float* o, const float* d, float reach) {
        for (int c = 0; c < 3; ++c) org[c] = o[c], dir[c] = d[c];
        tnear = zero, time = zero, tfar = reach;
        mask = INVALID, id = 0, flags = 0;
    }
};
using Cast1 = void (*)(void* scene, void* ray, void* args);

// the valid lanes of a packet of the first `count` rays (embree reads -1 as valid, 0 as not)
struct alignas(64) Lanes {
    int32_t v[K];
    explicit Lanes(int64_t count) { for (int l = 0; l < K; ++l) v[l] = l < count ? -1 : 0; }
};

template <typename T> std::vector<T> copy(const In<T>& a) { return std::vector<T>(a.data(), a.data() + a.size()); }
inline std::vector<uint8_t> copy(const In<bool>& a) { return std::vector<uint8_t>(a.data(), a.data() + a.size()); }

struct LightSample {
    bool ok;
    int32_t lmat;
    float w0, w1, w2, dist, scale, bsdf_pdf;
};

class LambertScene {
public:
    LambertScene(uintptr_t scene, uintptr_t intersect, uintptr_t occluded, In<float> normals,
                 In<int32_t> material_ids, In<bool> emissive, In<bool> two_sided, In<float> light_area_pdf,
                 In<float> emission, In<float> kd, In<double> cdf, In<int64_t> light_tris, In<float> v0,
                 In<float> e1, In<float> e2)
        : scene_(reinterpret_cast<void*>(scene)), intersect_(reinterpret_cast<CastK>(intersect)),
          occluded_(reinterpret_cast<Cast1>(occluded)), normals_(copy(normals)), material_ids_(copy(material_ids)),
          emissive_(copy(emissive)), two_sided_(copy(two_sided)), light_area_pdf_(copy(light_area_pdf)),
          emission_(copy(emission)), kd_(copy(kd)), cdf_(copy(cdf)), light_tris_(copy(light_tris)), v0_(copy(v0)),
          e1_(copy(e1)), e2_(copy(e2)) {
        need(scene && intersect && occluded, "embree scene and entry points");
        ntri_ = int64_t(material_ids_.size());
        nmat_ = int64_t(two_sided_.size());
        for (auto* a : {&normals_, &v0_, &e1_, &e2_}) need(int64_t(a->size()) == 3 * ntri_, "triangle arrays differ");
        need(int64_t(emissive_.size()) == ntri_ && int64_t(light_area_pdf_.size()) == ntri_, "triangle arrays differ");
        need(int64_t(emission_.size()) == 3 * nmat_ && int64_t(kd_.size()) == 3 * nmat_, "material arrays differ");
        for (int32_t mt : material_ids_) need(mt >= 0 && mt < nmat_, "material id out of range");
        need((cdf_.empty() && light_tris_.empty()) || (cdf_.size() >= 2 && light_tris_.size() == cdf_.size() - 1),
             "light distribution");
        for (int64_t k : light_tris_) need(k >= 0 && k < ntri_, "light triangle out of range");
    }

    // closest hits of rays 0..n: triangle (-1 for none) and distance (inf for none)
    void intersect(const float* o, const float* d, int64_t n, int32_t* prim, float* t) const {
        RayHitK ray;
        for (int64_t a = 0; a < n; a += K) {
            const int64_t count = n - a < K ? n - a : K;
            for (int l = 0; l < count; ++l) ray.set(l, o + 3 * (a + l), d + 3 * (a + l), far_);
            const Lanes lanes(count);
            intersect_(lanes.v, scene_, &ray, nullptr);
            for (int l = 0; l < count; ++l) {
                if (ray.geomID[l] == INVALID || ray.primID[l] >= uint32_t(ntri_)) {
                    prim[a + l] = -1;
                    t[a + l] = std::numeric_limits<float>::infinity();
                } else {
                    prim[a + l] = int32_t(ray.primID[l]);
                    t[a + l] = ray.tfar[l];
                }
            }
        }
    }

    // a point on an area light seen from p (unit normal n), as tracer.kernels._light_sample
    LightSample light_sample(const float* u, float p0, float p1, float p2, float n0, float n1, float n2,
                             float p_area, bool mis) const {
        const double x = double(u[0]);
        const int64_t nbins = int64_t(cdf_.size()) - 1;
        int64_t lo = 0, hi = nbins + 1;  // np.searchsorted(cdf, x, side="right")
        while (lo < hi) {
            const int64_t mid = (lo + hi) >> 1;
            if (cdf_[mid] <= x) lo = mid + 1;
            else hi = mid;
        }
        int64_t j = lo - 1 > 0 ? lo - 1 : 0;
        if (j > nbins - 1) j = nbins - 1;
        const int64_t k = light_tris_[j];
        const float* V = &v0_[3 * k];
        const float* E1 = &e1_[3 * k];
        const float* E2 = &e2_[3 * k];
        const float* N = &normals_[3 * k];
        const float su = std::sqrt(u[1]);
        const float b1 = one - su;
        const float b2 = u[2] * su;
        float w0 = V[0] + b1 * E1[0] + b2 * E2[0] - p0;
        float w1 = V[1] + b1 * E1[1] + b2 * E2[1] - p1;
        float w2 = V[2] + b1 * E1[2] + b2 * E2[2] - p2;
        const float dist2 = w0 * w0 + w1 * w1 + w2 * w2;
        const float dist = std::sqrt(dist2);
        w0 /= dist;
        w1 /= dist;
        w2 /= dist;
        const float cos_l = -(N[0] * w0 + N[1] * w1 + N[2] * w2);
        const int32_t lmat = material_ids_[k];
        const float cos_i = n0 * w0 + n1 * w1 + n2 * w2;
        if (!(cos_i > 0 && (cos_l > 0 || two_sided_[lmat]))) return {false, lmat, w0, w1, w2, dist, zero, zero};
        const float light_pdf = p_area * light_area_pdf_[k] * dist2 / pmax(std::fabs(cos_l), tiny);
        const float bsdf_pdf = pmax(cos_i, zero) * inv_pi;
        float w = one;
        if (mis) {
            const float a2 = light_pdf * light_pdf;
            const float s = a2 + bsdf_pdf * bsdf_pdf;
            w = s > 0 ? a2 / s : zero;
        }
        return {true, lmat, w0, w1, w2, dist, w / light_pdf, bsdf_pdf};
    }

    struct State {  // the live paths (rows 0..n) and the shadow rays of a bounce
        float *o, *d, *beta, *L, *prev_pdf;
        int64_t L_rows;
        const bool* specular;
        int64_t* idx;
        float* out;
        int64_t out_rows;
        bool* alive;
        int64_t* sh_rows;
        float *sh_o, *sh_d, *sh_t, *sh_val;
    };

    // one bounce in place: path i of the live paths moves to row j <= i (the j-th that hit); returns the
    // counts of the paths shaded and of the shadow rays
    std::pair<int64_t, int64_t> shade(const int32_t* prim, const float* t, int64_t n, const State& s,
                                      const float* u_nee, const float* u_bsdf, const float* cphi,
                                      const float* sphi, const float* u_rr, float p_area, float eps, float eps2,
                                      bool last, bool rr) const {
        need(last || !cdf_.empty(), "a scene without area lights has no light to sample");
        int64_t j = 0, g = 0;
        for (int64_t i = 0; i < n; ++i) {
            const int32_t k = prim[i];
            const int64_t r = s.idx[i];
            need(r >= 0 && r < s.out_rows, "path index out of range");
            if (k < 0) {  // a miss: no environment in these scenes, the path ends
                for (int c = 0; c < 3; ++c) s.out[3 * r + c] = s.L[3 * i + c];
                continue;
            }
            need(k < ntri_, "triangle index out of range");
            const float ti = t[i];
            const float dx = s.d[3 * i], dy = s.d[3 * i + 1], dz = s.d[3 * i + 2];
            const float p0 = s.o[3 * i] + ti * dx, p1 = s.o[3 * i + 1] + ti * dy, p2 = s.o[3 * i + 2] + ti * dz;
            const float* N = &normals_[3 * k];
            const float cos_o = N[0] * -dx + N[1] * -dy + N[2] * -dz;
            const bool front = cos_o > 0;
            const float sign = front ? one : -one;
            const float n0 = N[0] * sign, n1 = N[1] * sign, n2 = N[2] * sign;
            const int32_t mt = material_ids_[k];
            float l0 = s.L[3 * i], l1 = s.L[3 * i + 1], l2 = s.L[3 * i + 2];
            float b0 = s.beta[3 * i], b1 = s.beta[3 * i + 1], b2 = s.beta[3 * i + 2];
            const float* em = &emission_[3 * mt];
            if (emissive_[k] && (front || two_sided_[mt])) {
                float w = one;
                if (!s.specular[i]) {
                    const float light_pdf = p_area * light_area_pdf_[k] * (ti * ti) / pmax(std::fabs(cos_o), tiny);
                    const float a2 = s.prev_pdf[i] * s.prev_pdf[i];
                    const float sum = a2 + light_pdf * light_pdf;
                    w = sum > 0 ? a2 / sum : zero;
                }
                l0 += b0 * em[0] * w;
                l1 += b1 * em[1] * w;
                l2 += b2 * em[2] * w;
            }
            if (last) {
                s.out[3 * r] = l0, s.out[3 * r + 1] = l1, s.out[3 * r + 2] = l2;
                continue;
            }
            s.idx[j] = r;
            s.L[3 * j] = l0, s.L[3 * j + 1] = l1, s.L[3 * j + 2] = l2;
            const float q0 = p0 + eps * n0, q1 = p1 + eps * n1, q2 = p2 + eps * n2;  // just above the surface
            const LightSample ls = light_sample(u_nee + 4 * j, p0, p1, p2, n0, n1, n2, p_area, true);
            const float* kdm = &kd_[3 * mt];
            if (ls.ok) {
                const float* lem = &emission_[3 * ls.lmat];
                s.sh_rows[g] = j;
                s.sh_o[3 * g] = q0, s.sh_o[3 * g + 1] = q1, s.sh_o[3 * g + 2] = q2;
                s.sh_d[3 * g] = ls.w0, s.sh_d[3 * g + 1] = ls.w1, s.sh_d[3 * g + 2] = ls.w2;
                s.sh_t[g] = ls.dist * shrink - eps2;
                s.sh_val[3 * g] = kdm[0] * ls.bsdf_pdf * lem[0] * ls.scale * b0;
                s.sh_val[3 * g + 1] = kdm[1] * ls.bsdf_pdf * lem[1] * ls.scale * b1;
                s.sh_val[3 * g + 2] = kdm[2] * ls.bsdf_pdf * lem[2] * ls.scale * b2;
                ++g;
            }
            // cosine-weighted continuation: a uniform point on the unit sphere at the tip of n
            const float z = one - two * u_bsdf[3 * j + 1];
            const float rad = std::sqrt(pmax(zero, one - z * z));
            float x0 = n0 + rad * cphi[j], x1 = n1 + rad * sphi[j], x2 = n2 + z;
            const float length = std::sqrt(x0 * x0 + x1 * x1 + x2 * x2);
            if (length < short_) {
                x0 = n0, x1 = n1, x2 = n2;
            } else {
                x0 = x0 / length, x1 = x1 / length, x2 = x2 / length;
            }
            s.d[3 * j] = x0, s.d[3 * j + 1] = x1, s.d[3 * j + 2] = x2;
            s.prev_pdf[j] = (n0 * x0 + n1 * x1 + n2 * x2) * inv_pi;
            b0 = b0 * kdm[0], b1 = b1 * kdm[1], b2 = b2 * kdm[2];  // f cos / pdf = kd
            const float bmax = pmax(pmax(b0, b1), b2);
            if (rr) {
                const float q = pmin(bmax, one);
                const bool survive = u_rr[j] < q;
                if (survive) b0 = b0 / q, b1 = b1 / q, b2 = b2 / q;
                s.alive[j] = survive && bmax > 0;
            } else {
                s.alive[j] = bmax > 0;
            }
            s.beta[3 * j] = b0, s.beta[3 * j + 1] = b1, s.beta[3 * j + 2] = b2;
            s.o[3 * j] = q0, s.o[3 * j + 1] = q1, s.o[3 * j + 2] = q2;
            ++j;
        }
        return {j, g};
    }

    // the shadow rays cast, the visible light samples added, finished paths written out and the rest moved
    // up; their count
    int64_t settle(int64_t m, int64_t g, const State& s) const {
        RayHit1 ray;
        for (int64_t e = 0; e < g; ++e) {
            ray.set(s.sh_o + 3 * e, s.sh_d + 3 * e, pmin(s.sh_t[e], far_));
            occluded_(scene_, &ray, nullptr);
            if (!(ray.tfar < 0)) {  // embree marks a blocked ray with tfar = -inf
                const int64_t r = s.sh_rows[e];
                need(r >= 0 && r < s.L_rows, "shadow ray row out of range");
                for (int c = 0; c < 3; ++c) s.L[3 * r + c] += s.sh_val[3 * e + c];
            }
        }
        int64_t k = 0;
        for (int64_t j = 0; j < m; ++j) {
            if (s.alive[j]) {
                if (k != j) {
                    s.idx[k] = s.idx[j];
                    s.prev_pdf[k] = s.prev_pdf[j];
                    for (int c = 0; c < 3; ++c) {
                        s.o[3 * k + c] = s.o[3 * j + c], s.d[3 * k + c] = s.d[3 * j + c];
                        s.beta[3 * k + c] = s.beta[3 * j + c], s.L[3 * k + c] = s.L[3 * j + c];
                    }
                }
                ++k;
            } else {
                const int64_t r = s.idx[j];
                need(r >= 0 && r < s.out_rows, "path index out of range");
                for (int c = 0; c < 3; ++c) s.out[3 * r + c] = s.L[3 * j + c];
            }
        }
        return k;
    }

private:
    void* scene_;
    CastK intersect_;
    Cast1 occluded_;
    std::vector<float> normals_;
    std::vector<int32_t> material_ids_;
    std::vector<uint8_t> emissive_, two_sided_;
    std::vector<float> light_area_pdf_, emission_, kd_;
    std::vector<double> cdf_;
    std::vector<int64_t> light_tris_;
    std::vector<float> v0_, e1_, e2_;
    int64_t ntri_ = 0, nmat_ = 0;
};

}  // namespace lenslab_tracer
