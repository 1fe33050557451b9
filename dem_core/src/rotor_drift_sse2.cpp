// free_rotor_drift4 (rotor_drift_kernel.h) in the SSE2 form: the x86-64
// baseline, which every machine that runs the build can run.
#define FQ_LANE_KERNEL(name) name##sse2
#include "rotor_drift_kernel.h"
