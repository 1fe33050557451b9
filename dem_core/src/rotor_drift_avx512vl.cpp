// free_rotor_drift4 (rotor_drift_kernel.h) in the AVX-512VL form: the AVX2
// form's 256-bit code with 32 vector registers (EVEX encoding). CMake
// compiles this file alone with -mavx512f -mavx512vl (option
// FQ_AVX512VL_KERNELS); it runs only where lane_isa.h finds AVX-512VL on
// the processor.
#if !defined(__AVX512VL__) || !defined(__AVX2__)
#error "rotor_drift_avx512vl.cpp must be compiled with -mavx2 -mavx512f -mavx512vl"
#endif
#define FQ_LANE_KERNEL(name) name##avx512vl
#include "rotor_drift_kernel.h"
