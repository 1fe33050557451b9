// Which form of the SIMD lane kernels (lanes.h) runs: SSE2, the x86-64
// baseline every build can run; AVX2, one 256-bit register per four lanes,
// where the build has the AVX2 kernels (CMake option FQ_AVX2_KERNELS, on by
// default on x86-64) and the processor has AVX2; or AVX-512VL, the same
// 256-bit code in the EVEX encoding, which gives the kernels 32 vector
// registers instead of 16 (option FQ_AVX512VL_KERNELS), where the processor
// has AVX-512F and AVX-512VL. All forms give the same bits
// (tests/joints/test_joint_lanes.cpp, tests/dem_core/test_torque_free_rotation.cpp);
// the AVX2 form does the same lane work in about half the instructions of
// SSE2 (docs/performance_history.md, change 23), and the AVX-512VL form spills
// fewer of its vectors to the stack (change 37).
//
// The default is the fastest form available: avx512vl, then avx2, then
// sse2. The environment variable FRAMEQUAKE_SIMD (auto, sse2, avx2 or
// avx512vl) overrides it, read once at the first call; benchmarks use it to
// compare the forms in one sitting.
#pragma once

#include <cstdint>

namespace fq {

enum class LaneIsa : std::uint8_t { Sse2, Avx2, Avx512vl };

const char* lane_isa_name(LaneIsa isa);

// Built with this form's kernels, and the processor runs them.
bool lane_isa_available(LaneIsa isa);

// The form the kernels run now. Throws std::invalid_argument naming
// FRAMEQUAKE_SIMD when its value is not one of auto, sse2, avx2, avx512vl, or asks for
// a form that is not available.
LaneIsa active_lane_isa();

// Chooses the form from now on (tests, benchmarks). Returns false, and
// changes nothing, when `isa` is not available. Systems read the form when
// they prepare (JointSystem) or at every step (the rotation drift).
bool set_lane_isa(LaneIsa isa);

}  // namespace fq
