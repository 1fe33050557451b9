#include "dem_core/lane_isa.h"

#include <atomic>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace fq {

namespace {

bool processor_has_avx2() {
#if defined(__x86_64__) || defined(__i386__)
  // GCC's cpuid wrapper also checks that the OS saves the YMM registers.
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

bool processor_has_avx512vl() {
#if defined(__x86_64__) || defined(__i386__)
  // As above: libgcc's cpuid check counts AVX-512 only when the OS saves the
  // ZMM and mask registers (XCR0). The kernels of this form use -mavx2 code
  // too, so AVX2 is required as well.
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") && processor_has_avx2();
#else
  return false;
#endif
}

const char* why_unavailable(LaneIsa isa) {
  if (isa == LaneIsa::Avx512vl)
    return FQ_HAVE_AVX512VL_KERNELS ? "this processor has no AVX-512VL" : "built with FQ_AVX512VL_KERNELS=OFF";
  return FQ_HAVE_AVX2_KERNELS ? "this processor has no AVX2" : "built with FQ_AVX2_KERNELS=OFF";
}

LaneIsa initial_isa() {
  const char* env = std::getenv("FRAMEQUAKE_SIMD");
  const std::string wanted = env ? env : "auto";
  if (wanted.empty() || wanted == "auto") {
    for (const LaneIsa isa : {LaneIsa::Avx512vl, LaneIsa::Avx2})
      if (lane_isa_available(isa)) return isa;
    return LaneIsa::Sse2;
  }
  for (const LaneIsa isa : {LaneIsa::Sse2, LaneIsa::Avx2, LaneIsa::Avx512vl}) {
    if (wanted != lane_isa_name(isa)) continue;
    if (!lane_isa_available(isa))
      throw std::invalid_argument("FRAMEQUAKE_SIMD=" + wanted + ": the " + wanted + " kernels are not available (" +
                                  why_unavailable(isa) + "); unset it or use auto or sse2");
    return isa;
  }
  throw std::invalid_argument("FRAMEQUAKE_SIMD='" + wanted + "': expected auto, sse2, avx2 or avx512vl");
}

// 0: not yet read; else 1 + LaneIsa.
std::atomic<std::uint8_t> g_active{0};

}  // namespace

const char* lane_isa_name(LaneIsa isa) {
  switch (isa) {
    case LaneIsa::Avx2: return "avx2";
    case LaneIsa::Avx512vl: return "avx512vl";
    case LaneIsa::Sse2: break;
  }
  return "sse2";
}

bool lane_isa_available(LaneIsa isa) {
  switch (isa) {
    case LaneIsa::Avx2: return FQ_HAVE_AVX2_KERNELS && processor_has_avx2();
    case LaneIsa::Avx512vl: return FQ_HAVE_AVX512VL_KERNELS && processor_has_avx512vl();
    case LaneIsa::Sse2: break;
  }
  return true;
}

LaneIsa active_lane_isa() {
  std::uint8_t v = g_active.load(std::memory_order_relaxed);
  if (v == 0) {
    // Two threads may both read the environment; they find the same form.
    const LaneIsa isa = initial_isa();
    std::uint8_t expected = 0;
    g_active.compare_exchange_strong(expected, std::uint8_t(1 + int(isa)), std::memory_order_relaxed);
    v = g_active.load(std::memory_order_relaxed);
  }
  return LaneIsa(v - 1);
}

bool set_lane_isa(LaneIsa isa) {
  if (!lane_isa_available(isa)) return false;
  g_active.store(std::uint8_t(1 + int(isa)), std::memory_order_relaxed);
  return true;
}

}  // namespace fq
