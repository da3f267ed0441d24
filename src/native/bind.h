// What every binding of lenslab.cxx_kernels shares: the array types it takes and its one-line refusal.
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cstdint>
#include <stdexcept>

namespace lenslab::bind {

// an input: C-contiguous on the CPU, converted to this dtype and layout if need be
template <typename T> using In = nanobind::ndarray<const T, nanobind::c_contig, nanobind::device::cpu>;
// an output, written in place: the bindings mark it noconvert, so an array of another dtype or layout is refused
template <typename T> using Out = nanobind::ndarray<T, nanobind::c_contig, nanobind::device::cpu>;
// the warp kernels' arrays: float samples and coordinates, int64 shapes and offsets, bool masks
using InF = In<float>;
using InI = In<int64_t>;
using InB = In<bool>;
using OutF = Out<float>;

// refuse a call whose arrays or parameters disagree: nanobind raises it as a ValueError of one line
inline void need(bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(what);
}

}  // namespace lenslab::bind
