// The lane kernel of the joint system (joint_system.h, "Lane kernel"): a
// joint's points four at a time in SIMD lanes (dem_core/lanes.h), their springs'
// laws included, for joints whose points each carry a normal and two shear
// springs with one law per kind (the four-corner joints of the frames).
//
// This file decides which joints and points qualify and which SIMD form
// runs them; the kernels themselves are in joint_lane_kernels.h.
#include <algorithm>
#include <cstring>
#include <limits>
#include <string>
#include <unordered_map>

#include "dem_core/lane_isa.h"
#include "joints/joint_system.h"

namespace fq {

bool JointSystem::spring_is_plain_(std::size_t s) const {
  if (!alive_[s] || !has_prev_[s]) return false;
  switch (law_kind_[s]) {
    case SpringLawKind::LinearElastic:
      return true;
    case SpringLawKind::Trilinear: {
      if (yielded_[s]) return false;
      // The lane computes e = delta - 0.0; only an offset of exactly +0.0
      // gives e the bits of delta - offset for every delta.
      const double offset = trilinear_.state[std::size_t(law_index_[s])].plastic_offset_m;
      std::uint64_t bits;
      std::memcpy(&bits, &offset, sizeof bits);
      return bits == 0;
    }
    default:
      return false;
  }
}

void JointSystem::refresh_point_plain_(std::size_t p) {
  bool plain = true;
  for (auto s = std::size_t(point_first_[p]); s < std::size_t(point_first_[p + 1]); ++s)
    plain = plain && spring_is_plain_(s);
  point_plain_[p] = plain ? 1 : 0;
}

void JointSystem::prepare_lanes_() {
  const std::size_t nj = joint_body_a_.size();
  joint_lanes_.assign(nj, 0);
  joint_lane_type_.assign(nj, -1);
  lane_types_.clear();
  lane_attach_a_m_ = Vec3Columns{};
  lane_attach_b_m_ = Vec3Columns{};
  std::unordered_map<std::string, std::int32_t> type_lookup;  // bytes of a type -> index
  lane_laws_.clear();
  lane_form_ = active_lane_isa();
  point_plain_.assign(point_first_.empty() ? 0 : point_first_.size() - 1, 0);
  auto lane_law_of = [&](std::size_t s, LaneLaw& out) {
    const auto k = std::size_t(law_index_[s]);
    const double inf = std::numeric_limits<double>::infinity();
    switch (law_kind_[s]) {
      case SpringLawKind::Trilinear: {
        const TrilinearLaw& l = trilinear_.law[std::size_t(trilinear_.law_of[k])];
        out = {l.k0_t_Npm, l.k0_c_Npm, l.k1_t_Npm, l.k1_c_Npm, l.fy_t_N, l.fy_c_N, l.dy_t_m, l.dy_c_m, l.du_t_m, l.du_c_m};
        return true;
      }
      case SpringLawKind::LinearElastic: {
        // F* = k e with the bounds at +-infinity (k1 = 0, d_Y = 0): never
        // clamped, never past ultimate, the force the linear law gives.
        const double k0 = linear_.law[std::size_t(linear_.law_of[k])].stiffness_Npm;
        out = {k0, k0, 0.0, 0.0, inf, inf, 0.0, 0.0, inf, inf};
        return true;
      }
      default:
        return false;
    }
  };
  auto same = [](const LaneLaw& a, const LaneLaw& b) { return std::memcmp(&a, &b, sizeof(LaneLaw)) == 0; };
  for (std::size_t j = 0; j < nj; ++j) {
    bool ok = joint_first_point_[j + 1] > joint_first_point_[j];
    LaneLaw law[2] = {};
    double dashpot[2] = {0.0, 0.0};
    bool seen[2] = {false, false};
    for (auto p = std::size_t(joint_first_point_[j]); ok && p < std::size_t(joint_first_point_[j + 1]); ++p) {
      const auto first = std::size_t(point_first_[p]);
      // A normal spring (axis 2) and two shear springs (axes 0, 1), in that order.
      ok = point_first_[p + 1] - point_first_[p] == 3 && spring_axis_[first] == 2 &&
           spring_axis_[first + 1] == 0 && spring_axis_[first + 2] == 1;
      for (std::size_t k = 0; ok && k < 3; ++k) {
        const std::size_t s = first + k;
        const int kind = k == 0 ? 0 : 1;
        LaneLaw l;
        if (!lane_law_of(s, l)) {
          ok = false;
        } else if (!seen[kind]) {
          law[kind] = l;
          dashpot[kind] = dashpot_Nspm_[s];
          seen[kind] = true;
        } else {
          ok = same(law[kind], l) && std::memcmp(&dashpot[kind], &dashpot_Nspm_[s], sizeof(double)) == 0;
        }
      }
    }
    if (!ok || !settings_.lane_kernel) continue;
    joint_lanes_[j] = 1;
    std::int32_t law_id[2];
    for (int kind = 0; kind < 2; ++kind) {
      auto it = std::find_if(lane_laws_.begin(), lane_laws_.end(), [&](const LaneLaw& l) { return same(l, law[kind]); });
      if (it == lane_laws_.end()) it = lane_laws_.insert(lane_laws_.end(), law[kind]);
      law_id[kind] = std::int32_t(it - lane_laws_.begin());
    }
    // The joint's type: every value the kernel reads of it but its bodies,
    // as bytes (the same bytes, the same bits in every result).
    std::string key;
    auto put = [&key](const auto& v) { key.append(reinterpret_cast<const char*>(&v), sizeof v); };
    put(law_id[0]), put(law_id[1]), put(dashpot[0]), put(dashpot[1]);
    put(joint_break_[j].criterion), put(joint_break_[j].strain_limit);
    put(joint_spring_count_[j]), put(joint_normal_count_[j]);
    const auto first_point = std::size_t(joint_first_point_[j]), last_point = std::size_t(joint_first_point_[j + 1]);
    for (std::size_t p = first_point; p < last_point; ++p) {
      put(point_attach_a_m_.x[p]), put(point_attach_a_m_.y[p]), put(point_attach_a_m_.z[p]);
      put(point_attach_b_m_.x[p]), put(point_attach_b_m_.y[p]), put(point_attach_b_m_.z[p]);
    }
    const auto [it, added] = type_lookup.emplace(key, std::int32_t(lane_types_.size()));
    if (added) {
      LaneType t;
      t.law_n = law_id[0], t.law_s = law_id[1];
      t.c_n_Nspm = dashpot[0], t.c_s_Nspm = dashpot[1];
      t.fracture = joint_break_[j];
      t.springs = joint_spring_count_[j], t.normal_springs = joint_normal_count_[j];
      t.first_attach = std::int32_t(lane_attach_a_m_.size());
      for (std::size_t p = first_point; p < last_point; ++p) {
        lane_attach_a_m_.push_back(point_attach_a_m_[p]);
        lane_attach_b_m_.push_back(point_attach_b_m_[p]);
      }
      lane_types_.push_back(t);
    }
    joint_lane_type_[j] = it->second;
  }
}

// The form prepare_lanes_ chose (a form the build lacks is never chosen:
// lane_isa_available).
void JointSystem::update_lane_frames_(const BodyStore& bodies, std::size_t first, std::size_t last) {
  switch (lane_form_) {
#if FQ_HAVE_AVX512VL_KERNELS
    case LaneIsa::Avx512vl:
      return update_lane_frames_avx512vl_(bodies, first, last);
#endif
#if FQ_HAVE_AVX2_KERNELS
    case LaneIsa::Avx2:
      return update_lane_frames_avx2_(bodies, first, last);
#endif
    default:
      return update_lane_frames_sse2_(bodies, first, last);
  }
}

void JointSystem::joint_step_lanes_(const BodyStore& bodies, std::size_t j) {
  switch (lane_form_) {
#if FQ_HAVE_AVX512VL_KERNELS
    case LaneIsa::Avx512vl:
      return joint_step_lanes_avx512vl_(bodies, j);
#endif
#if FQ_HAVE_AVX2_KERNELS
    case LaneIsa::Avx2:
      return joint_step_lanes_avx2_(bodies, j);
#endif
    default:
      return joint_step_lanes_sse2_(bodies, j);
  }
}

std::size_t JointSystem::lane_joint_count() const {
  return std::size_t(std::count(joint_lanes_.begin(), joint_lanes_.end(), std::uint8_t(1)));
}

}  // namespace fq
