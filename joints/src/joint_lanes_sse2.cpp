// The joint lane kernels (joint_lane_kernels.h) in the SSE2 form: the
// x86-64 baseline, which every machine that runs the build can run.
#define FQ_LANE_KERNEL(name) name##sse2_
#include "joint_lane_kernels.h"
