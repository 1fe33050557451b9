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

LaneIsa initial_isa() {
  const char* env = std::getenv("FRAMEQUAKE_SIMD");
  const std::string wanted = env ? env : "auto";
  if (wanted.empty() || wanted == "auto")
    return lane_isa_available(LaneIsa::Avx2) ? LaneIsa::Avx2 : LaneIsa::Sse2;
  if (wanted == "sse2") return LaneIsa::Sse2;
  if (wanted == "avx2") {
    if (!lane_isa_available(LaneIsa::Avx2))
      throw std::invalid_argument(
          std::string("FRAMEQUAKE_SIMD=avx2: the AVX2 kernels are not available (") +
          (FQ_HAVE_AVX2_KERNELS ? "this processor has no AVX2" : "built with FQ_AVX2_KERNELS=OFF") +
          "); unset it or use auto or sse2");
    return LaneIsa::Avx2;
  }
  throw std::invalid_argument("FRAMEQUAKE_SIMD='" + wanted + "': expected auto, sse2 or avx2");
}

// 0: not yet read; else 1 + LaneIsa.
std::atomic<std::uint8_t> g_active{0};

}  // namespace

const char* lane_isa_name(LaneIsa isa) { return isa == LaneIsa::Avx2 ? "avx2" : "sse2"; }

bool lane_isa_available(LaneIsa isa) {
  if (isa == LaneIsa::Sse2) return true;
  return FQ_HAVE_AVX2_KERNELS && processor_has_avx2();
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
