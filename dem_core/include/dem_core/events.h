// Events: what happened, to what, when and where. Joints and contacts never
// change topology in the middle of a stage; they collect events during the
// force stage and apply them in finish_step, in ascending id, so the event
// list is the same for any thread count (STYLE.md 3.2).
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "dem_core/types.h"

namespace fq {

class StateWriter;  // dem_core/state_io.h
class StateReader;

enum class EventKind : std::uint8_t {
  SpringYielded = 0,   // a spring left its elastic branch for the first time
  SpringDeleted = 1,   // a spring passed its ultimate strain and carries nothing more
  JointBroken = 2,     // a joint met its fracture criterion; the pair may now collide
  Instability = 3,     // non-finite or exploding state detected
};
const char* event_kind_name(EventKind kind);

struct Event {
  double time_s = 0.0;
  std::int64_t step = 0;
  EventKind kind = EventKind::SpringYielded;
  std::int32_t joint_id = -1;    // -1 when not a joint event
  BodyId body_a = kNoBody;
  BodyId body_b = kNoBody;
  std::int32_t spring_index = -1;  // index within the joint, -1 for the whole joint
  const char* mode = "";           // failure mode, a static string: "tension", "compression", "shear", ...
  double force_N = 0.0;            // spring or joint force at the event (N)
  Vec3 position_m = Vec3::Zero();  // where (world frame, m)
};

// A pointer to a static copy of `mode` that lives as long as the program:
// Event::mode must stay a plain static string, so a mode read back from a
// checkpoint is interned here (thread-safe; one copy per distinct text).
const char* intern_event_mode(std::string_view mode);

// Append-only log; observers read new entries since their last visit.
class EventLog {
 public:
  void add(const Event& e) { events_.push_back(e); }
  const std::vector<Event>& all() const { return events_; }
  std::size_t size() const { return events_.size(); }
  std::size_t count(EventKind kind) const;
  void clear() { events_.clear(); }
  // Checkpoints (state_io.h): every event, bit for bit; load replaces the log.
  void save_state(StateWriter& out) const;
  void load_state(StateReader& in);

 private:
  std::vector<Event> events_;
};

}  // namespace fq
