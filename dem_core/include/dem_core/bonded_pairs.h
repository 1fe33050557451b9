// Pairs of bodies held together by intact joints. Joints register pairs and
// release them in the same post-step routine that breaks the joint; contacts
// skip registered pairs (STYLE.md 3.2: "when a joint breaks, contacts between
// the two members switch on in the same place"). Lives in dem_core so that
// joints and contacts share it without depending on each other.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "dem_core/types.h"

namespace fq {

class StateWriter;  // dem_core/state_io.h
class StateReader;

class BondedPairs {
 public:
  void add(BodyId a, BodyId b) { ++count_[key(a, b)]; }
  // Called once per joint that breaks; the pair becomes free when no intact
  // joint holds it any more.
  void release(BodyId a, BodyId b) {
    auto it = count_.find(key(a, b));
    if (it != count_.end() && --it->second <= 0) {
      count_.erase(it);
      released_.emplace_back(a < b ? a : b, a < b ? b : a);
    }
  }
  // Every pair that became free, in the order it happened (lower id first).
  // Contacts read it to start such pairs from their overlap at release.
  const std::vector<std::pair<BodyId, BodyId>>& released() const { return released_; }
  bool bonded(BodyId a, BodyId b) const { return count_.count(key(a, b)) != 0; }
  std::size_t size() const { return count_.size(); }
  // Checkpoints (state_io.h): the held pairs with their joint counts, and
  // the release log. Defined in simulation.cpp (the simulation owns the set).
  void save_state(StateWriter& out) const;
  void load_state(StateReader& in);

 private:
  static std::uint64_t key(BodyId a, BodyId b) {
    const auto lo = static_cast<std::uint32_t>(a < b ? a : b);
    const auto hi = static_cast<std::uint32_t>(a < b ? b : a);
    return (std::uint64_t(hi) << 32) | lo;
  }
  std::unordered_map<std::uint64_t, int> count_;
  std::vector<std::pair<BodyId, BodyId>> released_;
};

}  // namespace fq
