#include "dem_core/events.h"

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

}  // namespace fq
