// The joint lane kernels (joint_lane_kernels.h) in the AVX2 form. CMake
// compiles this file alone with -mavx2 (option FQ_AVX2_KERNELS); it runs
// only where dem_core/lane_isa.h finds AVX2 on the processor.
#if !defined(__AVX2__)
#error "joint_lanes_avx2.cpp must be compiled with -mavx2"
#endif
#define FQ_LANE_KERNEL(name) name##avx2_
#include "joint_lane_kernels.h"
