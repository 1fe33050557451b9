// The series of fast_sincos (rotation.cpp), shared with the lane form of
// the rotation drift (rotor_drift_kernel.h), which must use the same
// constants to give the same bits.
#pragma once

namespace fq::rotation_series {
// |angle| < kSeriesAngle: the first omitted terms (x^8/8!, x^9/9!) are <
// 1e-26, far below the 1e-16 relative round-off of the result.
constexpr double kSeriesAngle = 2e-3;
// Products with the reciprocals: a division by 6 cannot be turned into a
// multiplication by the compiler (1/6 is inexact), and costs ~15 cycles.
constexpr double k6 = 1.0 / 6.0, k20 = 1.0 / 20.0, k42 = 1.0 / 42.0, k12 = 1.0 / 12.0, k30 = 1.0 / 30.0;
}  // namespace fq::rotation_series
