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

#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(_OPENMP)
#include <omp.h>
#endif

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

// Threads a parallel region would get (1 without OpenMP).
inline int worker_count() {
#if defined(_OPENMP)
  return omp_get_max_threads();
#else
  return 1;
#endif
}

// Indices 0 .. n-1 of cost cost[i] (any unit, >= 0) cut into `parts`
// contiguous ranges of about equal total cost: part p is [first[p],
// first[p+1]). A range may be empty.
inline void split_by_cost(const double* cost, std::int64_t n, int parts, std::vector<std::int64_t>& first) {
  first.assign(std::size_t(parts) + 1, n);
  first[0] = 0;
  double total = 0.0;
  for (std::int64_t i = 0; i < n; ++i) total += cost[i];
  if (!(total > 0.0)) {  // no costs known: equal counts
    for (int q = 1; q < parts; ++q) first[std::size_t(q)] = n * q / parts;
    return;
  }
  double done = 0.0;
  int p = 1;
  for (std::int64_t i = 0; i < n && p < parts; ++i) {
    // Cut before i once the cost so far reaches p shares.
    while (p < parts && done >= total * double(p) / double(parts)) first[std::size_t(p++)] = i;
    done += cost[i];
  }
}

// Contiguous ranges of uneven cost (split_by_cost): part p runs on thread p
// in every call, so, as with parallel_for_static, the same thread handles
// the same indices from one step to the next while the ranges stay put.
template <class Body>
inline void parallel_for_parts(const std::vector<std::int64_t>& first, bool parallel, Body&& body) {
#if defined(_OPENMP)
  const int parts = int(first.size()) - 1;
  if (parallel && parts > 1) {
#pragma omp parallel num_threads(parts)
    {
      const int nt = omp_get_num_threads();
      for (int p = omp_get_thread_num(); p < parts; p += nt)
        for (std::int64_t i = first[std::size_t(p)]; i < first[std::size_t(p) + 1]; ++i) body(i);
    }
    return;
  }
#else
  (void)parallel;
#endif
  for (std::int64_t i = first.front(); i < first.back(); ++i) body(i);
}

// n items cut into chunks of about `target` items each for sums that must
// not depend on the thread count: each chunk is summed alone and the chunk
// sums are added in chunk order, so the chunks depend on n alone. Above one
// chunk, their number is rounded up to a multiple of `multiple` and they are
// of equal size to one item, so a static schedule over the chunks gives
// every thread the same number of items (to one item per chunk) whenever the
// thread count divides `multiple`. Chunk c is [begin(c), begin(c + 1)).
struct EqualChunks {
  std::size_t items = 0, count = 0;
  EqualChunks(std::size_t n, std::size_t target, std::size_t multiple) : items(n) {
    count = (n + target - 1) / target;
    if (count > 1) count = (count + multiple - 1) / multiple * multiple;
  }
  std::size_t begin(std::size_t c) const { return c * items / count; }
};

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
