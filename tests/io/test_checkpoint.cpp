// Checkpoint and restart (io/checkpoint.h, Simulation::save_state): a run
// saved at step k, loaded into a scene freshly built from the same case and
// continued, ends bitwise identical to the run that was never interrupted.
//
// Expected values come from the uninterrupted run itself, computed by the
// same code with no checkpoint in between: the claim under test is
// equality, bit for bit (state hash over every body's pose and velocities,
// the ledger's bytes, every provider's energy books, the event list, the
// contact list), not any particular number. Both scenarios of the issue are
// covered, with the checkpoint step chosen from the uninterrupted run and
// the scenario asserted, not assumed:
//   - the arm's joint breaks AFTER the checkpoint (springs have yielded and
//     cycled, hysteretic and plastic histories are live at the checkpoint);
//   - the checkpoint lies AFTER the break while contacts are active (a
//     released pair in overlap, contact histories, friction).
// A second check: saving the loaded state again gives the very same bytes,
// so nothing the simulation carries is left out of the round trip.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstring>
#include <memory>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "checkpoint_case.h"
#include "dem_core/state_io.h"
#include "io/case_file.h"
#include "io/case_runner.h"
#include "io/checkpoint.h"
#include "io_test_util.h"

namespace fq {
namespace {

constexpr double kDuration_s = 0.4;  // 40 000 steps: break at ~0.06 s, the arm lands at ~0.25 s

CaseDef arm_case(const test::TempDir& dir) {
  dir.write("shake.txt", test::sine_record(1.0));
  return load_case_file(dir.write("arm.yaml", test::arm_case(kDuration_s, "shake.txt")));
}

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void step_to(Simulation& sim, std::int64_t n) {
  while (sim.steps_done() < n) ASSERT_TRUE(sim.step());
}

// Stored and dissipated energies as the providers book them (the ledger
// gathers them only when an observer samples).
EnergyLedger provider_books(const Simulation& sim) {
  EnergyLedger l;
  for (const auto& p : sim.providers()) p->report_energy(l);
  return l;
}

void expect_same_events(const EventLog& a, const EventLog& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    const Event& x = a.all()[k];
    const Event& y = b.all()[k];
    EXPECT_EQ(x.step, y.step) << "event " << k;
    EXPECT_EQ(std::memcmp(&x.time_s, &y.time_s, sizeof(double)), 0) << "event " << k;
    EXPECT_EQ(x.kind, y.kind) << "event " << k;
    EXPECT_EQ(x.joint_id, y.joint_id);
    EXPECT_EQ(x.body_a, y.body_a);
    EXPECT_EQ(x.body_b, y.body_b);
    EXPECT_EQ(x.spring_index, y.spring_index);
    EXPECT_STREQ(x.mode, y.mode);
    EXPECT_EQ(std::memcmp(&x.force_N, &y.force_N, sizeof(double)), 0) << "event " << k;
    EXPECT_EQ(x.position_m, y.position_m) << "event " << k;
  }
}

// Bitwise comparison of two finished scenes.
void expect_identical(const Scene& a, const Scene& b) {
  const Simulation& x = *a.simulation;
  const Simulation& y = *b.simulation;
  EXPECT_EQ(x.steps_done(), y.steps_done());
  EXPECT_EQ(x.state_hash(), y.state_hash());
  const EnergyLedger lx = x.ledger(), ly = y.ledger();
  EXPECT_EQ(std::memcmp(&lx, &ly, sizeof lx), 0) << "ledgers differ";
  const EnergyLedger px = provider_books(x), py = provider_books(y);
  EXPECT_EQ(std::memcmp(&px, &py, sizeof px), 0) << "provider energy books differ";
  expect_same_events(x.events(), y.events());
  ASSERT_EQ(a.contacts->contact_count(), b.contacts->contact_count());
  for (std::size_t k = 0; k < a.contacts->contact_count(); ++k) {
    EXPECT_EQ(a.contacts->contacts()[k].shear_spring_N, b.contacts->contacts()[k].shear_spring_N);
    EXPECT_EQ(a.contacts->contacts()[k].reference_depth_m, b.contacts->contacts()[k].reference_depth_m);
  }
  EXPECT_EQ(a.contacts->broad_phase_rebuilds(), b.contacts->broad_phase_rebuilds());
  EXPECT_EQ(a.joints->counts().broken, b.joints->counts().broken);
  for (std::size_t s = 0; s < a.joints->spring_count(); ++s)
    EXPECT_EQ(a.joints->spring_plastic_J(s), b.joints->spring_plastic_J(s)) << "spring " << s;
}

// Runs to `checkpoint_step`, checks the scenario with `at_checkpoint`,
// saves, loads into a fresh scene, continues to the end; compares with
// `reference` (the uninterrupted run).
template <class Check>
void resume_and_compare(const CaseDef& def, const Scene& reference, std::int64_t checkpoint_step, Check at_checkpoint) {
  Scene first = build_scene(def);
  step_to(*first.simulation, checkpoint_step);
  at_checkpoint(first);
  StateWriter saved;
  first.simulation->save_state(saved);

  Scene second = build_scene(def);
  StateReader in(saved.bytes());
  second.simulation->load_state(in);
  EXPECT_EQ(in.remaining(), 0u);
  EXPECT_EQ(second.simulation->state_hash(), first.simulation->state_hash());
  StateWriter again;
  second.simulation->save_state(again);
  EXPECT_TRUE(again.bytes() == saved.bytes()) << "saving the loaded state gives other bytes: something is not restored";

  step_to(*second.simulation, reference.simulation->steps_done());
  expect_identical(reference, second);
}

struct Reference {
  test::TempDir dir;
  CaseDef def;
  Scene scene;
  std::int64_t break_step = -1;          // step of the JointBroken event
  std::int64_t first_arm_contact = -1;   // first step after the break with a contact of the arm
};

constexpr BodyId kArm = 2;  // ground body 0, column 1, arm 2 (model.h body order)

bool arm_touching(const Scene& s) {
  for (const ContactPoint& c : s.contacts->contacts())
    if (c.body_a == kArm || c.body_b == kArm) return true;
  return false;
}

// The uninterrupted run, made once for all tests of this file (it is the
// expensive part under the sanitizers).
const Reference& reference() {
  static const std::unique_ptr<Reference> ref = [] {
    auto r = std::make_unique<Reference>();
    r->def = arm_case(r->dir);
    r->scene = build_scene(r->def);
    Simulation& sim = *r->scene.simulation;
    const std::int64_t end = sim.total_steps();
    while (sim.steps_done() < end) {
      EXPECT_TRUE(sim.step());
      if (r->break_step < 0)
        for (const Event& e : sim.events().all())
          if (e.kind == EventKind::JointBroken) r->break_step = e.step;
      if (r->break_step >= 0 && r->first_arm_contact < 0 && arm_touching(r->scene))
        r->first_arm_contact = sim.steps_done();
    }
    return r;
  }();
  return *ref;
}

TEST(Checkpoint, ResumedRunIsBitwiseIdenticalAcrossAJointBreak) {
  const Reference& ref = reference();
  ASSERT_GT(ref.break_step, 1000) << "the arm's joint must break in this scene";
  ASSERT_GT(ref.first_arm_contact, ref.break_step) << "the falling arm must touch something";
  // Checkpoint before the break, once springs have yielded (plastic and
  // hysteretic state live), so the break happens after the resume.
  resume_and_compare(ref.def, ref.scene, ref.break_step - 1000, [](const Scene& at) {
    EXPECT_GT(at.simulation->events().count(EventKind::SpringYielded), 0u);
    EXPECT_EQ(at.simulation->events().count(EventKind::JointBroken), 0u);
  });
}

TEST(Checkpoint, ResumedRunIsBitwiseIdenticalAfterABreakWithContactsActive) {
  const Reference& ref = reference();
  ASSERT_GT(ref.first_arm_contact, ref.break_step);
  // A few hundred steps into the arm's first contact: tangential springs
  // and the released pair's reference depths are live.
  resume_and_compare(ref.def, ref.scene, ref.first_arm_contact + 300, [](const Scene& at) {
    EXPECT_EQ(at.simulation->events().count(EventKind::JointBroken), 1u);
    EXPECT_TRUE(arm_touching(at)) << "the checkpoint must lie while the arm is in contact";
  });
}

TEST(Checkpoint, StateForAnotherSceneIsRefusedWithAReason) {
  test::TempDir dir;
  const CaseDef def = arm_case(dir);
  Scene a = build_scene(def);
  step_to(*a.simulation, 10);
  StateWriter saved;
  a.simulation->save_state(saved);

  // Same bodies, but without contacts: the provider list differs.
  CaseDef no_contacts = def;
  no_contacts.contact.reset();
  Scene b = build_scene(no_contacts);
  StateReader in(saved.bytes());
  try {
    b.simulation->load_state(in);
    FAIL() << "a state with other providers was accepted";
  } catch (const StateFormatError& e) {
    EXPECT_NE(std::string(e.what()).find("providers"), std::string::npos) << e.what();
  }

  // A joint section of another layout (version 4 had no flags for the
  // books a break leaves open, joint_system_state.cpp) is refused with both
  // versions named.
  {
    std::string other = saved.bytes();
    // A section is its marker (state_io.h), its name's length and its name;
    // the simulation frames each provider's state in a section of the
    // provider's name, in which JointSystem::save_state opens its own.
    const std::string tag = std::string("\x4E\x10\xC7\x5E\x06\0\0\0\0\0\0\0", 12) + "joints";
    const std::size_t framed = other.find(tag + tag);
    ASSERT_NE(framed, std::string::npos);
    const std::size_t at = framed + tag.size();
    std::uint32_t version = 0;
    std::memcpy(&version, other.data() + at + tag.size(), sizeof version);
    EXPECT_EQ(version, 5u);
    version = 4;
    std::memcpy(other.data() + at + tag.size(), &version, sizeof version);
    Scene c = build_scene(def);
    StateReader old_layout(other);
    try {
      c.simulation->load_state(old_layout);
      ADD_FAILURE() << "a joint state of version 4 was accepted";
    } catch (const StateFormatError& e) {
      EXPECT_NE(std::string(e.what()).find("joint state version 4, this build reads 5"), std::string::npos)
          << e.what();
    }
  }

  // Every truncation of the state is refused by the reader, never read past.
  for (std::size_t cut : {std::size_t(0), std::size_t(7), saved.bytes().size() / 2, saved.bytes().size() - 1}) {
    Scene c = build_scene(def);
    StateReader part(std::string_view(saved.bytes()).substr(0, cut));
    EXPECT_THROW(c.simulation->load_state(part), StateFormatError) << "cut at " << cut;
  }
}

TEST(Checkpoint, FileFramingDetectsDamage) {
  test::TempDir dir;
  const auto file = dir.path() / "checkpoint.bin";
  const std::string payload = "some state bytes";
  write_checkpoint_file(file, payload);
  EXPECT_EQ(read_checkpoint_file(file), payload);

  std::string bytes = read_file(file);
  auto expect_refused = [&](const std::string& content, const char* why) {
    dir.write("checkpoint.bin", content);
    try {
      read_checkpoint_file(file);
      ADD_FAILURE() << "accepted a file that is " << why;
    } catch (const CheckpointError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(file.string()), std::string::npos) << m;
      EXPECT_NE(m.find(why), std::string::npos) << m;
    }
  };
  std::string flipped = bytes;
  flipped[24 + 3] ^= 0x10;  // inside the payload
  expect_refused(flipped, "damaged");
  expect_refused(bytes.substr(0, bytes.size() - 3), "truncated");
  expect_refused("time_s,kinetic_J\n0,0\n", "not a framequake checkpoint");
  std::string other_version = bytes;
  other_version[8] = 9;
  expect_refused(other_version, "format version 9");
  std::filesystem::remove(file);
  expect_refused("", "not a framequake checkpoint");
  std::filesystem::remove(file);
  try {
    read_checkpoint_file(file);
    ADD_FAILURE() << "accepted a missing file";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
  // A pipe in its place is refused, not opened: opening a FIFO blocks until
  // a writer comes, which Ctrl-C cannot stop (CLI probe).
  ASSERT_EQ(::mkfifo(file.c_str(), 0600), 0);
  try {
    read_checkpoint_file(file);
    ADD_FAILURE() << "accepted a pipe";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("is not a regular file"), std::string::npos) << e.what();
  }
}

// changed_case_files names each file whose fingerprint differs, by its
// place in the case (case file, then records), and what one list has and
// the other not; a moved project (other paths, same bytes) has nothing to
// name. The lists are made here, so the expected words follow from them.
TEST(Checkpoint, ChangedCaseFilesNamesEachFileThatDiffers) {
  const std::vector<CaseFileFingerprint> then = {{"case file", "/p/a.yaml", 1}, {"ground-motion record", "/p/x.AT2", 2}};
  EXPECT_EQ(changed_case_files(then, then), "");
  EXPECT_EQ(changed_case_files(then, {{"case file", "/q/a.yaml", 1}, {"ground-motion record", "/q/x.AT2", 2}}), "")
      << "moved with the same bytes";
  EXPECT_EQ(changed_case_files(then, {{"case file", "/p/a.yaml", 1}, {"ground-motion record", "/p/x.AT2", 3}}),
            "the ground-motion record '/p/x.AT2' has changed");
  EXPECT_EQ(changed_case_files(then, {{"case file", "/p/a.yaml", 5}, {"ground-motion record", "/p/y.AT2", 4}}),
            "the case file '/p/a.yaml' has changed; the ground-motion record '/p/y.AT2' differs from the one the run "
            "began with ('/p/x.AT2')");
  EXPECT_EQ(changed_case_files(then, {{"case file", "/p/a.yaml", 5},
                                      {"ground-motion record", "/p/x.AT2", 2},
                                      {"ground-motion record", "/p/z.AT2", 6}}),
            "the case file '/p/a.yaml' has changed; the case now reads the ground-motion record '/p/z.AT2' as well");
  EXPECT_EQ(changed_case_files(then, {{"case file", "/p/a.yaml", 5}}),
            "the case file '/p/a.yaml' has changed; the case no longer reads the ground-motion record '/p/x.AT2'");
}

}  // namespace
}  // namespace fq
