// free_rotor_drift4 (rotor_drift_kernel.h) in the AVX2 form. CMake compiles
// this file alone with -mavx2 (option FQ_AVX2_KERNELS); it runs only where
// lane_isa.h finds AVX2 on the processor.
#if !defined(__AVX2__)
#error "rotor_drift_avx2.cpp must be compiled with -mavx2"
#endif
#define FQ_LANE_KERNEL(name) name##avx2
#include "rotor_drift_kernel.h"
