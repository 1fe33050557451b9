// Pieces the benchmark programs share: the process's CPU time, and the
// final state hash of each scene per thread count, compared at the end of
// the program (results must be bitwise the same for any thread count).
#pragma once

#include <cstdint>
#include <cstdio>
#include <ctime>
#include <map>
#include <string>
#include <utility>

namespace fq::bench {

// CPU seconds of the whole process (all threads): on a shared machine the
// wall time also counts time the process waited for a core.
inline double process_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

class ThreadHashes {
 public:
  void record(const std::string& scene, int threads, std::uint64_t hash) { hashes_[{scene, threads}] = hash; }
  // One line per scene and thread count above 1 that also ran on 1 thread;
  // returns 1 when any final state differs from the 1-thread one, else 0.
  int compare_with_one_thread() const {
    int status = 0;
    for (const auto& [key, hash] : hashes_) {
      if (key.second == 1) continue;
      const auto one = hashes_.find({key.first, 1});
      if (one == hashes_.end()) continue;
      const bool same = one->second == hash;
      std::printf("%s: final state 1 thread vs %d threads: %s\n", key.first.c_str(), key.second,
                  same ? "identical" : "DIFFERENT");
      if (!same) status = 1;
    }
    return status;
  }

 private:
  std::map<std::pair<std::string, int>, std::uint64_t> hashes_;
};

inline ThreadHashes& thread_hashes() {
  static ThreadHashes hashes;
  return hashes;
}

}  // namespace fq::bench
