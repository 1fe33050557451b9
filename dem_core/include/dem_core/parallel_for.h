// Loops that use OpenMP threads only when they are worth it.
//
// `#pragma omp parallel for if (false)` still enters the OpenMP runtime:
// libgomp builds a one-thread team for the region (an aligned heap
// allocation, freed at its end, plus the team bookkeeping), about a
// microsecond each time. A 16-body frame runs about ten such regions per
// step, which cost more than its whole force computation. These helpers
// decide before the pragma, so a small loop never touches the runtime.
//
// body(i) is called for i = 0 .. n-1. With `parallel` true the iterations
// are split over the threads (schedule as named); each index must write only
// what it owns, as everywhere in the engine, so the results do not depend on
// the thread count.
#pragma once

#include <cstdint>

namespace fq {

template <class Body>
inline void parallel_for_static(std::int64_t n, bool parallel, Body&& body) {
#if defined(_OPENMP)
  if (parallel) {
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) body(i);
    return;
  }
#else
  (void)parallel;
#endif
  for (std::int64_t i = 0; i < n; ++i) body(i);
}

// Dynamic schedule, one index at a time (chunks of uneven cost).
template <class Body>
inline void parallel_for_dynamic(std::int64_t n, bool parallel, Body&& body) {
#if defined(_OPENMP)
  if (parallel) {
#pragma omp parallel for schedule(dynamic, 1)
    for (std::int64_t i = 0; i < n; ++i) body(i);
    return;
  }
#else
  (void)parallel;
#endif
  for (std::int64_t i = 0; i < n; ++i) body(i);
}

}  // namespace fq
