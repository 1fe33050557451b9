#include "scene_output.h"

#include <limits>
#include <memory>
#include <sstream>
#include <vector>

#include "io/json_writer.h"

namespace fq {

namespace {

// Damage state of each member from the state of its joints, written on the
// member's body cell (the bodies block comes first with one cell per body,
// so body i is cell i: vtk_frame_writer.h). 0 intact: every joint elastic
// (or no joint); 1 yielded: a joint yielded, none broken; 2 damaged: a joint
// broken, another still holding; 3 detached: every joint broken. The
// ground is no member: -1, the array's fill (it took the states of the
// support joints, and a frame coloured by damage showed it "detached";
// output probe).
void add_member_damage(const Simulation& sim, const JointSystem& js, VtkFrameBuilder& frame) {
  const std::size_t bodies = sim.bodies().size();
  std::vector<std::int32_t> joints(bodies, 0), broken(bodies, 0), yielded(bodies, 0);
  for (std::size_t j = 0; j < js.joint_count(); ++j) {
    const JointStatus st = js.joint_status(j);
    for (const BodyId b : {js.joint_body_a(j), js.joint_body_b(j)}) {
      const auto i = std::size_t(b);
      if (i >= bodies) continue;
      ++joints[i];
      if (st == JointStatus::Broken) ++broken[i];
      if (st == JointStatus::Yielded) ++yielded[i];
    }
  }
  const auto damage = frame.cell_array("damage_state", VtkArrayType::Int32, 1, -1);
  for (std::size_t i = 0; i < bodies; ++i) {
    if (sim.bodies().info[i].kind == MemberKind::Ground) continue;  // stays -1
    double state = 0.0;
    if (broken[i] > 0)
      state = broken[i] == joints[i] ? 3.0 : 2.0;
    else if (yielded[i] > 0)
      state = 1.0;
    frame.set(damage, VtkFrameBuilder::Index(i), state);
  }
}

}  // namespace

void attach_joint_output(RunOutput& output, const JointSystem& joints, const std::vector<std::string>& nodes,
                         const std::vector<std::string>& names) {
  const JointSystem* js = &joints;
  output.set_joint_names(nodes, names);
  output.add_cell_block("springs", [js, nodes, names](const Simulation& sim, VtkFrameBuilder& frame) {
    add_member_damage(sim, *js, frame);
    // Indexed by joint_id: what a spring's joint_id stands for in the case.
    frame.add_field("joint_names", names);
    frame.add_field("joint_nodes", nodes);
    const std::size_t n = js->spring_count();
    const auto force = frame.cell_array("spring_force_N", VtkArrayType::Float64, 1, std::nan(""));
    const auto ratio = frame.cell_array("strain_ratio", VtkArrayType::Float64, 1, std::nan(""));
    const auto state = frame.cell_array("spring_state", VtkArrayType::Int32, 1, -1);
    const auto role = frame.cell_array("spring_role", VtkArrayType::Int32, 1, -1);
    const auto joint = frame.cell_array("joint_id", VtkArrayType::Int32, 1, -1);
    const auto broken = frame.cell_array("joint_broken", VtkArrayType::Int32, 1, -1);
    for (std::size_t s = 0; s < n; ++s) {
      // Ends where the bodies of this frame are (the stored ends are the
      // last force evaluation's, a step before).
      const auto [end_a, end_b] = js->spring_ends_now_m(sim.bodies(), s);
      const auto a = frame.add_point(end_a);
      const auto b = frame.add_point(end_b);
      const auto cell = frame.add_cell(VtkCellType::Line, {a, b});
      const auto j = std::size_t(js->spring_joint()[s]);
      frame.set(force, cell, js->spring_force_N()[s]);
      frame.set(ratio, cell, js->spring_strain_ratio(s));
      frame.set(state, cell, double(js->spring_status(s)));
      frame.set(role, cell, double(js->spring_role()[s]));
      frame.set(joint, cell, double(j));
      frame.set(broken, cell, js->joint_status(j) == JointStatus::Broken ? 1.0 : 0.0);
    }
  });
  output.add_history_column("joints_intact_count", [js](const Simulation&) { return double(js->counts().intact); });
  output.add_history_column("joints_yielded_count", [js](const Simulation&) { return double(js->counts().yielded); });
  output.add_history_column("joints_broken_count", [js](const Simulation&) { return double(js->counts().broken); });
}

void attach_contact_output(RunOutput& output, const ContactSystem& contacts) {
  const ContactSystem* cs = &contacts;
  output.add_cell_block("contacts", [cs](const Simulation& /*sim*/, VtkFrameBuilder& frame) {
    const auto force = frame.cell_array("contact_force_N", VtkArrayType::Float64, 3, std::nan(""));
    const auto normal = frame.cell_array("contact_normal", VtkArrayType::Float64, 3, std::nan(""));
    const auto depth = frame.cell_array("contact_depth_m", VtkArrayType::Float64, 1, std::nan(""));
    const auto sliding = frame.cell_array("contact_sliding", VtkArrayType::Int32, 1, -1);
    for (const ContactPoint& c : cs->contacts()) {
      const auto p = frame.add_point(c.position_m);
      const auto cell = frame.add_cell(VtkCellType::Vertex, {p});
      frame.set(force, cell, c.force_N());
      frame.set(normal, cell, c.normal);
      frame.set(depth, cell, c.depth_m);
      frame.set(sliding, cell, c.sliding ? 1.0 : 0.0);
    }
  });
  output.add_history_column("contact_points_count", [cs](const Simulation&) { return double(cs->contact_count()); });
  output.add_history_column("ground_normal_force_N", [cs](const Simulation&) { return cs->ground_normal_force_N(); });
}

void attach_base_force_output(RunOutput& output, const JointSystem* joints, const ContactSystem* contacts) {
  // Summed once per row: the three columns of a row share it.
  struct Cached {
    std::int64_t step = -1;
    Vec3 force_N = Vec3::Zero();
  };
  auto cache = std::make_shared<Cached>();
  auto base_force = [joints, contacts, cache](const Simulation& sim) {
    if (cache->step != sim.steps_done()) {
      cache->step = sim.steps_done();
      cache->force_N.setZero();
      if (joints) cache->force_N += joints->force_from_fixed_bodies_N(sim.bodies());
      if (contacts) cache->force_N += contacts->force_from_fixed_bodies_N(sim.bodies());
    }
    return cache->force_N;
  };
  output.add_history_column("base_shear_x_N", [base_force](const Simulation& sim) { return base_force(sim).x(); });
  output.add_history_column("base_shear_y_N", [base_force](const Simulation& sim) { return base_force(sim).y(); });
  output.add_history_column("base_reaction_z_N", [base_force](const Simulation& sim) { return base_force(sim).z(); });
}

void add_joint_summary(RunOutput& output, const JointSystem& joints, const EventLog& events,
                       const std::vector<std::string>& labels, const std::vector<std::string>& names) {
  const JointCounts c = joints.counts();
  std::ostringstream counts;
  counts << "{\"total\": " << joints.joint_count() << ", \"intact\": " << c.intact << ", \"yielded\": " << c.yielded
         << ", \"broken\": " << c.broken << "}";
  output.add_summary_field("joints", counts.str());
  output.add_summary_field("first_joint_failure_time_s", JsonWriter::number(first_joint_failure_time_s(events)));
  const std::string first = first_joint_failure_label(events, labels);
  output.add_summary_field("first_joint_failure", first.empty() ? std::string("null") : JsonWriter::quote(first));
  // The same joint's id (joint_id of events.csv and the frames) and name
  // (their joint_name and joint_names), so that the weak point found here
  // can be followed into the other outputs.
  const std::int32_t id = first_joint_failure_id(events);
  output.add_summary_field("first_joint_failure_joint_id", id >= 0 ? std::to_string(id) : std::string("null"));
  output.add_summary_field("first_joint_failure_joint_name", id >= 0 && std::size_t(id) < names.size()
                                                                 ? JsonWriter::quote(names[std::size_t(id)])
                                                                 : std::string("null"));
}

void add_contact_summary(RunOutput& output, const ContactSystem& contacts, const BodyStore& bodies) {
  const ContactPressPeak& p = contacts.press_peak();
  if (!(p.ratio > 0.0)) {
    output.add_summary_field("contact_press_peak", "null");
    return;
  }
  std::ostringstream f;
  f << "{\"depth_m\": " << JsonWriter::number(p.depth_m)
    << ", \"half_thickness_m\": " << JsonWriter::number(p.half_dimension_m)
    << ", \"ratio\": " << JsonWriter::number(p.ratio) << ", \"time_s\": " << JsonWriter::number(p.time_s)
    << ", \"body_a\": " << JsonWriter::quote(p.body_a == kNoBody ? std::string("ground") : bodies.info[std::size_t(p.body_a)].name)
    << ", \"body_b\": " << JsonWriter::quote(bodies.info[std::size_t(p.body_b)].name)
    << ", \"measured_body\": " << JsonWriter::quote(bodies.info[std::size_t(p.measured)].name) << "}";
  output.add_summary_field("contact_press_peak", f.str());
}

namespace {

// The first failure event: a spring deleted or a joint broken; null when
// no joint failed.
const Event* first_joint_failure(const EventLog& events) {
  for (const Event& e : events.all())
    if (e.kind == EventKind::SpringDeleted || e.kind == EventKind::JointBroken) return &e;
  return nullptr;
}

}  // namespace

std::int32_t first_joint_failure_id(const EventLog& events) {
  const Event* e = first_joint_failure(events);
  return e ? e->joint_id : -1;
}

std::string first_joint_failure_label(const EventLog& events, const std::vector<std::string>& labels) {
  const Event* e = first_joint_failure(events);
  if (!e) return "";
  return e->joint_id >= 0 && std::size_t(e->joint_id) < labels.size() ? labels[std::size_t(e->joint_id)]
                                                                       : "joint " + std::to_string(e->joint_id);
}

double first_joint_failure_break_time_s(const EventLog& events) {
  const Event* e = first_joint_failure(events);
  if (e)
    for (const Event& b : events.all())
      if (b.kind == EventKind::JointBroken && b.joint_id == e->joint_id && b.time_s >= e->time_s) return b.time_s;
  return std::numeric_limits<double>::quiet_NaN();
}

double first_joint_failure_time_s(const EventLog& events) {
  const Event* e = first_joint_failure(events);
  return e ? e->time_s : std::numeric_limits<double>::quiet_NaN();
}

void attach_storey_output(RunOutput& output, StoreyDriftMonitor& monitor) {
  StoreyDriftMonitor* m = &monitor;
  for (std::size_t i = 0; i < monitor.storeys().size(); ++i) {
    const std::string prefix = "storey" + std::to_string(monitor.storeys()[i].number) + "_drift";
    auto sampled = [m](const Simulation& sim) -> StoreyDriftMonitor& {
      m->sample(sim.bodies(), sim.steps_done(), sim.time_s());
      return *m;
    };
    output.add_history_column(prefix + "_x_m", [=](const Simulation& sim) { return sampled(sim).drift_m(i).x(); });
    output.add_history_column(prefix + "_y_m", [=](const Simulation& sim) { return sampled(sim).drift_m(i).y(); });
    output.add_history_column(prefix + "_ratio_x_rad",
                              [=](const Simulation& sim) { return sampled(sim).drift_ratio_rad(i).x(); });
    output.add_history_column(prefix + "_ratio_y_rad",
                              [=](const Simulation& sim) { return sampled(sim).drift_ratio_rad(i).y(); });
  }
}

void add_storey_summary(RunOutput& output, const StoreyDriftMonitor& monitor, bool assessed) {
  const AssessmentDef& a = monitor.limits();
  JsonWriter limits(0);
  limits.begin_object()
      .key("safety_drift_ratio_rad")
      .value(a.safety_drift_ratio_rad)
      .key("collapse_drift_ratio_rad")
      .value(a.collapse_drift_ratio_rad)
      .key("criterion")
      .value(
          "storey drift = mean horizontal displacement of its columns' top points relative to their bottom points; "
          "verdict collapsed if the peak drift ratio (x-y magnitude, taken at every step) reached "
          "collapse_drift_ratio_rad, damaged if it exceeded safety_drift_ratio_rad, else standing")
      .end_object();
  output.add_summary_field("assessment", limits.str());
  JsonWriter w(0);
  w.begin_array();
  for (std::size_t i = 0; i < monitor.storeys().size(); ++i) {
    const Storey& s = monitor.storeys()[i];
    const StoreyDriftRecord& r = monitor.records()[i];
    w.begin_object()
        .key("storey")
        .value(s.number)
        .key("bottom_z_m")
        .value(s.bottom_z_m)
        .key("height_m")
        .value(s.height_m())
        .key("columns")
        .value(s.columns.size())
        .key("peak_drift_ratio_rad")
        .value(r.peak_ratio_rad)
        .key("peak_drift_ratio_x_rad")
        .value(r.peak_ratio_x_rad)
        .key("peak_drift_ratio_y_rad")
        .value(r.peak_ratio_y_rad)
        .key("peak_time_s")
        .value(r.peak_time_s)
        .key("peak_floor_drift_ratio_rad")
        .value(r.peak_floor_ratio_rad)
        .key("peak_top_slip_m")
        .value(r.peak_top_slip_m)
        .key("peak_base_slip_m")
        .value(r.peak_base_slip_m)
        .key("peak_twist_ratio_rad")
        .value(r.peak_twist_ratio_rad)
        .key("peak_column_drift_ratio_rad")
        .value(r.peak_column_ratio_rad)
        .key("peak_column");
    if (r.peak_column >= 0)
      w.value(s.column_names[std::size_t(r.peak_column)]);
    else
      w.null();
    w.key("residual_drift_ratio_x_rad")
        .value(r.residual_ratio_x_rad)
        .key("residual_drift_ratio_y_rad")
        .value(r.residual_ratio_y_rad)
        .key("residual_window_s")
        .value(r.residual_window_s)
        .key("final_drift_ratio_x_rad")
        .value(r.final_ratio_x_rad)
        .key("final_drift_ratio_y_rad")
        .value(r.final_ratio_y_rad)
        .key("collapse_time_s");
    if (r.collapse_time_s >= 0.0)
      w.value(r.collapse_time_s);
    else
      w.null();
    w.key("verdict").value(assessed ? storey_verdict_name(monitor.verdict(i)) : "not_assessed").end_object();
  }
  w.end_array();
  output.add_summary_field("storeys", w.str());
}

}  // namespace fq
