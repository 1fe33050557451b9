#include "dem_core/events.h"

#include <mutex>
#include <set>
#include <string>

#include "dem_core/state_io.h"

namespace fq {

const char* event_kind_name(EventKind kind) {
  switch (kind) {
    case EventKind::SpringYielded: return "spring_yielded";
    case EventKind::SpringDeleted: return "spring_deleted";
    case EventKind::JointBroken: return "joint_broken";
    case EventKind::Instability: return "instability";
  }
  return "unknown";
}

std::size_t EventLog::count(EventKind kind) const {
  std::size_t n = 0;
  for (const Event& e : events_)
    if (e.kind == kind) ++n;
  return n;
}

const char* intern_event_mode(std::string_view mode) {
  // std::set nodes never move, so the c_str() handed out stays valid.
  static std::mutex lock;
  static std::set<std::string, std::less<>> modes;
  const std::lock_guard<std::mutex> guard(lock);
  auto it = modes.find(mode);
  if (it == modes.end()) it = modes.emplace(mode).first;
  return it->c_str();
}

void EventLog::save_state(StateWriter& out) const {
  out.section("events");
  out.u64(events_.size());
  for (const Event& e : events_) {
    out.f64(e.time_s);
    out.i64(e.step);
    out.u8(static_cast<std::uint8_t>(e.kind));
    out.pod(e.joint_id);
    out.pod(e.body_a);
    out.pod(e.body_b);
    out.pod(e.spring_index);
    out.str(e.mode ? e.mode : "");
    out.f64(e.force_N);
    out.vec3(e.position_m);
  }
}

void EventLog::load_state(StateReader& in) {
  in.section("events");
  const std::uint64_t n = in.u64("event count");
  // Each event takes at least 60 bytes: a damaged count cannot make us allocate.
  if (n > in.remaining() / 60) in.fail("event count larger than the data left");
  std::vector<Event> events(static_cast<std::size_t>(n));
  for (Event& e : events) {
    e.time_s = in.f64("event time");
    e.step = in.i64("event step");
    const std::uint8_t kind = in.u8("event kind");
    if (std::string(event_kind_name(static_cast<EventKind>(kind))) == "unknown") in.fail("unknown event kind");
    e.kind = static_cast<EventKind>(kind);
    e.joint_id = in.pod<std::int32_t>("event joint id");
    e.body_a = in.pod<BodyId>("event body a");
    e.body_b = in.pod<BodyId>("event body b");
    e.spring_index = in.pod<std::int32_t>("event spring index");
    e.mode = intern_event_mode(in.str("event mode"));
    e.force_N = in.f64("event force");
    e.position_m = in.vec3("event position");
  }
  events_ = std::move(events);
}

}  // namespace fq
