// Checkpoint and restart through the command line: `framequake run CASE
// --checkpoint-every S` killed with SIGKILL after a checkpoint exists, then
// `framequake resume DIR`, ends with exactly the output of a run that was
// never interrupted: the same summary.json state_hash (bitwise-equal final
// state), and byte-identical history.csv, events.csv and case.pvd (rows and
// frames cut back to the checkpoint and written again). The reference is
// the same binary run without interruption; the claim is equality.
// A damaged, truncated or foreign checkpoint, or a case changed since,
// ends in exit code 2 with a message naming checkpoint.bin and the fault,
// and leaves the folder as it was.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <thread>

#include "../io/checkpoint_case.h"
#include "app_process.h"

namespace {

namespace fs = std::filesystem;
using fq_test::AppProcess;
using fq_test::read_text;
using fq_test::run_app;
using fq_test::TempDir;

void write_text(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

std::string state_hash(const fs::path& summary) {
  std::smatch m;
  const std::string s = read_text(summary);
  if (!std::regex_search(s, m, std::regex("\"state_hash\": \"([0-9a-f]{16})\""))) return "";
  return m[1];
}

struct Fixture {
  TempDir dir;
  fs::path case_file;
  Fixture() {
    write_text(dir.path() / "shake.txt", fq::test::sine_record(1.0));
    case_file = dir.path() / "arm.yaml";
    write_text(case_file, fq::test::arm_case(0.4, "shake.txt"));
  }
  // Starts a checkpointed run into `out` and kills it (SIGKILL) as soon as
  // its first checkpoint is on disk. Returns the exit code (137 = killed).
  // `case_arg`: the case as the command line gives it (default: its
  // absolute path; the child runs in this test's working folder).
  int run_and_kill(const fs::path& out, const std::string& case_arg = "") {
    AppProcess p({"run", case_arg.empty() ? case_file.string() : case_arg, "--out", out.string(), "--quiet",
                  "--checkpoint-every", "0.02"},
                 dir.path());
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!fs::exists(out / "checkpoint.bin") && std::chrono::steady_clock::now() < give_up)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    p.signal(SIGKILL);
    return p.wait();
  }
};

TEST(CheckpointCli, KilledRunResumedGivesTheUninterruptedOutput) {
  Fixture f;
  const fs::path ref = f.dir.path() / "ref", out = f.dir.path() / "out";
  ASSERT_EQ(run_app({"run", f.case_file.string(), "--out", ref.string(), "--quiet"}, f.dir.path()).code, 0);
  ASSERT_EQ(f.run_and_kill(out), 128 + SIGKILL) << "the run must be killed before it ends";
  ASSERT_FALSE(fs::exists(out / "summary.json"));
  ASSERT_LT(fs::file_size(out / "history.csv"), fs::file_size(ref / "history.csv")) << "nothing left to resume";

  const auto r = run_app({"resume", out.string(), "--quiet"}, f.dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string hash = state_hash(ref / "summary.json");
  ASSERT_FALSE(hash.empty());
  EXPECT_EQ(state_hash(out / "summary.json"), hash);
  for (const char* name : {"history.csv", "events.csv", "case.pvd"})
    EXPECT_TRUE(read_text(out / name) == read_text(ref / name)) << name << " differs from the uninterrupted run";
  EXPECT_NE(read_text(out / "events.csv").find("joint_broken"), std::string::npos) << "the run must span the break";
  // It ends with the lines a run ends with (apps/run_outcome.cpp): the
  // joint that broke, named, and the energy balance.
  EXPECT_NE(r.out.find(" broken); first failure: "), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("first failure: none"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("framequake: energy balance error "), std::string::npos) << r.out;
  // The resumed process's speed counts its own steps, those after the
  // checkpoint, over its own wall time (it divided all the run's steps by
  // it before).
  auto number = [&](const std::string& key) {
    std::smatch m;
    const std::string text = read_text(out / "summary.json");
    EXPECT_TRUE(std::regex_search(text, m, std::regex("\"" + key + "\": ([0-9.eE+-]+)"))) << key;
    return m.empty() ? 0.0 : std::stod(m[1]);
  };
  const double steps = number("steps"), wall = number("wall_time_s"), rate = number("steps_per_second");
  ASSERT_GT(wall, 0.0);
  EXPECT_LT(rate * wall, 0.99 * steps) << "steps " << steps << ", wall " << wall << " s, rate " << rate;
  EXPECT_GT(rate * wall, 0.0);
}

// A project folder moved after the run was killed (case, record and
// output together): resume names the missing case file and --case; with
// --case it ends as the uninterrupted run does (workflow probe: it could
// not be resumed at all).
TEST(CheckpointCli, AMovedCaseIsResumedWithCase) {
  Fixture f;
  const fs::path ref = f.dir.path() / "ref", out = f.dir.path() / "out";
  ASSERT_EQ(run_app({"run", f.case_file.string(), "--out", ref.string(), "--quiet"}, f.dir.path()).code, 0);
  ASSERT_EQ(f.run_and_kill(out), 128 + SIGKILL);
  const fs::path moved = f.dir.path() / "moved";
  fs::create_directories(moved);
  for (const char* name : {"arm.yaml", "shake.txt", "out"}) fs::rename(f.dir.path() / name, moved / name);
  const auto lost = run_app({"resume", (moved / "out").string(), "--quiet"}, f.dir.path());
  EXPECT_EQ(lost.code, 2) << lost.err;
  // Appended piece by piece: gcc 12 warns falsely (-Wstringop-overflow) of
  // the inlined concatenation of temporaries.
  std::string expected = "'";
  expected += f.case_file.string();
  expected += "', is not there any more; if it was moved (with its records), give its new place with --case FILE";
  EXPECT_NE(lost.err.find(expected), std::string::npos) << lost.err;
  const auto r =
      run_app({"resume", (moved / "out").string(), "--case", (moved / "arm.yaml").string(), "--quiet"}, f.dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(state_hash(moved / "out" / "summary.json"), state_hash(ref / "summary.json"));
  EXPECT_TRUE(read_text(moved / "out" / "history.csv") == read_text(ref / "history.csv"));
}

// A new run into the folder of a killed run that resume could continue
// replaces it, as a run replaces any earlier one, and says so.
TEST(CheckpointCli, ARunReplacingAResumableRunSaysSo) {
  Fixture f;
  const fs::path out = f.dir.path() / "out";
  ASSERT_EQ(f.run_and_kill(out), 128 + SIGKILL);
  const auto again = run_app({"run", f.case_file.string(), "--out", out.string(), "--quiet"}, f.dir.path());
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.err.find("note: the output folder " + out.string() + " held an unfinished run (killed, no summary) "
                           "that `framequake resume " + out.string() +
                           "` could have continued from its checkpoint; this run replaces it"),
            std::string::npos)
      << again.err;
  // Its own folder, finished: nothing to say the next time.
  const auto third = run_app({"run", f.case_file.string(), "--out", out.string(), "--quiet"}, f.dir.path());
  EXPECT_EQ(third.err.find("held an unfinished run"), std::string::npos) << third.err;
}

// A run into a folder that another run still holds (its lock; a
// checkpointed run has a checkpoint and no summary while it runs) is
// refused, and says nothing of replacing a killed run: the note was told
// before the lock was tried (review probe), so a live run read as killed.
TEST(CheckpointCli, ARunIntoAFolderInUseDoesNotCallItsRunKilled) {
  Fixture f;
  const fs::path out = f.dir.path() / "out";
  ASSERT_EQ(f.run_and_kill(out), 128 + SIGKILL);
  const int fd = ::open(out.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  const auto r = run_app({"run", f.case_file.string(), "--out", out.string(), "--quiet"}, f.dir.path());
  ::close(fd);
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("is in use by another framequake process"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("held an unfinished run"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(out / "checkpoint.bin"));
}

// A run killed while writing a history row leaves history.csv with rows
// past its checkpoint and a last row cut short. Resume reads the storey
// drifts of the rows before the checkpoint, and read them before cutting the
// file back to the checkpoint: the cut row failed it with "a row has the
// wrong length" (seen as a rare failure of the test below). Here the cut
// row is made on purpose after a kill; resume must give the uninterrupted
// run's output, as in KilledRunResumedGivesTheUninterruptedOutput.
TEST(CheckpointCli, ResumeIgnoresARowCutByTheKill) {
  Fixture f;
  const fs::path ref = f.dir.path() / "ref", out = f.dir.path() / "out";
  ASSERT_EQ(run_app({"run", f.case_file.string(), "--out", ref.string(), "--quiet"}, f.dir.path()).code, 0);
  ASSERT_EQ(f.run_and_kill(out), 128 + SIGKILL) << "the run must be killed before it ends";
  std::ofstream(out / "history.csv", std::ios::binary | std::ios::app) << "0.5,1.25e-3,7";  // no newline
  const auto r = run_app({"resume", out.string(), "--quiet"}, f.dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(state_hash(out / "summary.json"), state_hash(ref / "summary.json"));
  EXPECT_TRUE(read_text(out / "history.csv") == read_text(ref / "history.csv"));
}

// Resume's estimate of the output still to come: history.csv already holds
// the rows before the checkpoint. With a row every two steps (50 001 rows
// over the 1 s run, about 1 000 on disk at the first checkpoint) resume
// counted the whole file as one row and announced about 10 GB (docs probe:
// 18 GB for a 16 MB run of frame B). What is left here is some 10 MB: no
// note.
TEST(CheckpointCli, ResumeEstimatesOnlyTheOutputStillToCome) {
  Fixture f;
  std::string text = fq::test::arm_case(1.0, "shake.txt");
  const std::string every_ms = "history_interval_s: 0.001";
  ASSERT_NE(text.find(every_ms), std::string::npos);
  text.replace(text.find(every_ms), every_ms.size(), "history_interval_s: 2.0e-5");
  write_text(f.case_file, text);
  const fs::path out = f.dir.path() / "out";
  ASSERT_EQ(f.run_and_kill(out), 128 + SIGKILL) << "the run must be killed before it ends";
  const auto r = run_app({"resume", out.string()}, f.dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("this run will write"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find(" GB"), std::string::npos) << r.err;
}

// A run that chose central difference with --integrator over the case
// file's integrator resumes with central difference too (checkpoints are
// written by central-difference runs only): the same state as the run
// never interrupted. Resume took the file's velocity_verlet before and
// ended, exit 0, in another state.
TEST(CheckpointCli, ResumeKeepsTheIntegratorChosenOnTheCommandLine) {
  Fixture f;
  std::string text = read_text(f.case_file);
  const std::string time = "time: {dt_s: 1.0e-5, duration_s: ";
  ASSERT_NE(text.find(time), std::string::npos);
  text.replace(text.find(time), time.size(), "time: {integrator: velocity_verlet, dt_s: 1.0e-5, duration_s: ");
  write_text(f.case_file, text);
  const fs::path ref = f.dir.path() / "ref", out = f.dir.path() / "out";
  ASSERT_EQ(run_app({"run", f.case_file.string(), "--integrator", "central_difference", "--out", ref.string(), "--quiet"},
                    f.dir.path())
                .code,
            0);
  AppProcess p({"run", f.case_file.string(), "--integrator", "central_difference", "--out", out.string(), "--quiet",
                "--checkpoint-every", "0.02"},
               f.dir.path());
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!fs::exists(out / "checkpoint.bin") && std::chrono::steady_clock::now() < give_up)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  p.signal(SIGKILL);
  ASSERT_EQ(p.wait(), 128 + SIGKILL) << "the run must be killed before it ends";
  const auto r = run_app({"resume", out.string(), "--quiet"}, f.dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(read_text(out / "summary.json").find("\"integrator\": \"central_difference\""), std::string::npos);
  const std::string hash = state_hash(ref / "summary.json");
  ASSERT_FALSE(hash.empty());
  EXPECT_EQ(state_hash(out / "summary.json"), hash);
}

TEST(CheckpointCli, BadCheckpointOrChangedCaseIsRefusedWithExitCode2) {
  Fixture f;
  const fs::path out = f.dir.path() / "out";
  ASSERT_EQ(f.run_and_kill(out), 128 + SIGKILL);
  const fs::path ckpt = out / "checkpoint.bin";
  const std::string good = read_text(ckpt);
  const std::string history = read_text(out / "history.csv");

  auto expect_refused = [&](const char* fault) {
    const auto r = run_app({"resume", out.string(), "--quiet"}, f.dir.path());
    EXPECT_EQ(r.code, 2) << fault << ": " << r.err;
    EXPECT_NE(r.err.find("checkpoint.bin"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(fault), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
    // Nothing half written: the folder is as the killed run left it.
    EXPECT_FALSE(fs::exists(out / "summary.json"));
    EXPECT_TRUE(read_text(out / "history.csv") == history);
  };
  std::string flipped = good;
  flipped[flipped.size() / 2] = char(flipped[flipped.size() / 2] ^ 0x01);
  write_text(ckpt, flipped);
  expect_refused("damaged");
  write_text(ckpt, good.substr(0, good.size() / 3));
  expect_refused("truncated");
  write_text(ckpt, "time_s,kinetic_J\n0,0\n");
  expect_refused("not a framequake checkpoint");

  // A changed case file or record is named, and the other file is not
  // said to have changed (the refusal said "that file or one of its
  // ground-motion records" until the checkpoint kept each file's own
  // fingerprint).
  write_text(ckpt, good);
  const std::string case_text = read_text(f.case_file);
  write_text(f.case_file, case_text + "# edited after the checkpoint\n");
  expect_refused(("the case file '" + f.case_file.string() + "' has changed").c_str());
  {
    const auto r = run_app({"resume", out.string(), "--quiet"}, f.dir.path());
    EXPECT_EQ(r.err.find("record"), std::string::npos) << r.err;
  }
  write_text(f.case_file, case_text);
  const fs::path record = f.dir.path() / "shake.txt";
  const std::string record_text = read_text(record);
  write_text(record, record_text + "\n");
  expect_refused(("the ground-motion record '" + record.string() + "' has changed").c_str());
  {
    const auto r = run_app({"resume", out.string(), "--quiet"}, f.dir.path());
    EXPECT_EQ(r.err.find("the case file '"), std::string::npos) << r.err;
  }
  write_text(record, record_text);

  fs::remove(ckpt);
  expect_refused("does not exist");

  // With the intact checkpoint back, the same folder resumes.
  write_text(ckpt, good);
  EXPECT_EQ(run_app({"resume", out.string(), "--quiet"}, f.dir.path()).code, 0);

  // A completed run has nothing to resume: refused, its summary untouched
  // (a probe's second resume rewrote it with the wall time of a no-op).
  const std::string summary = read_text(out / "summary.json");
  const auto again = run_app({"resume", out.string(), "--quiet"}, f.dir.path());
  EXPECT_EQ(again.code, 2) << again.err;
  EXPECT_NE(again.err.find("completed (summary.json); there is nothing to resume"), std::string::npos) << again.err;
  EXPECT_TRUE(read_text(out / "summary.json") == summary);

  // A run stopped before its first step left no checkpoint: the refusal
  // says so instead of asking whether --checkpoint-every was given.
  const fs::path early = f.dir.path() / "early";
  fs::create_directories(early);
  write_text(early / "summary.json", "{\n  \"status\": \"stopped\",\n  \"steps\": 0,\n  \"dt_s\": 1e-05\n}\n");
  const auto e = run_app({"resume", early.string(), "--quiet"}, f.dir.path());
  EXPECT_EQ(e.code, 2) << e.err;
  EXPECT_NE(e.err.find("was stopped before its first step, so it left no checkpoint"), std::string::npos) << e.err;
}

// A run given its case by a relative path resolves the record relative to
// the working folder; resume reloads the case by its absolute path. A
// changed record is still named as the same file that changed, not as
// another file (a probe's resume said the record "differs from the one the
// run began with ('shake.txt')" for the very same file).
TEST(CheckpointCli, AChangedRecordOfACaseGivenByARelativePathIsNamedAsChanged) {
  Fixture f;
  const fs::path out = f.dir.path() / "out";
  const fs::path relative_case = fs::relative(f.case_file, fs::current_path());
  ASSERT_TRUE(relative_case.is_relative()) << relative_case;
  ASSERT_EQ(f.run_and_kill(out, relative_case.string()), 128 + SIGKILL);
  const fs::path record = f.dir.path() / "shake.txt";
  write_text(record, read_text(record) + "\n");
  const auto r = run_app({"resume", out.string(), "--quiet"}, f.dir.path());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("since then the ground-motion record '" + record.lexically_normal().string() + "' has changed"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("differs"), std::string::npos) << r.err;
}

// A run begun by the framequake before events.csv's node and joint_name
// columns (its header ends with body_b_name) is not resumed into rows of
// two more columns: refused, naming events.csv. The old file is made here
// by renaming the two columns within the same length (the length must
// match the checkpoint's).
TEST(CheckpointCli, ResumeRefusesAnEventsFileWithOtherColumns) {
  Fixture f;
  const fs::path out = f.dir.path() / "out";
  ASSERT_EQ(f.run_and_kill(out), 128 + SIGKILL);
  std::string events = read_text(out / "events.csv");
  const std::string columns = ",node,joint_name\n";
  const std::size_t at = events.find(columns);
  ASSERT_NE(at, std::string::npos) << events.substr(0, 200);
  ASSERT_EQ(at, events.find('\n') + 1 - columns.size()) << "the last columns of the header";
  events.replace(at, columns.size(), ",xxxx,yyyyyyyyyy\n");
  write_text(out / "events.csv", events);
  const auto r = run_app({"resume", out.string(), "--quiet"}, f.dir.path());
  EXPECT_EQ(r.code, 3) << r.err;  // an output error, as for a file cut shorter than the checkpoint
  EXPECT_NE(r.err.find("events.csv' has the columns of another framequake version"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "summary.json") && read_text(out / "summary.json").find("completed") != std::string::npos);
}

// A folder another process holds (its lock, as a running run or resume
// holds it) is an output error for resume, exit 3 and "error:", as it is
// for run; it was an "internal error" with the undocumented exit 4
// (failure-mode probe). The folder is left as the killed run left it.
TEST(CheckpointCli, ResumeIntoAFolderInUseIsAnOutputError) {
  Fixture f;
  const fs::path out = f.dir.path() / "out";
  ASSERT_EQ(f.run_and_kill(out), 128 + SIGKILL);
  const std::string history = read_text(out / "history.csv");
  const int fd = ::open(out.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  const auto r = run_app({"resume", out.string(), "--quiet"}, f.dir.path());
  ::close(fd);
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("is in use by another framequake process"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  EXPECT_TRUE(read_text(out / "history.csv") == history);
}

// Checkpoints so frequent that writing them costs more than the run are
// noted before it starts, with their number and size (a probe's checkpoint
// every step turned a 0.15 s run into 36 s, silently); a usual interval
// gives no note. The arm case runs 0.4 s at dt = 1e-5 s: every 0.2 ms is
// 2000 checkpoints, above the 1000 noted; every 20 ms is 20.
TEST(CheckpointCli, VeryFrequentCheckpointsAreNoted) {
  Fixture f;
  const auto many = run_app({"run", f.case_file.string(), "--out", (f.dir.path() / "many").string(), "--quiet",
                             "--checkpoint-every", "0.0002"},
                            f.dir.path());
  ASSERT_EQ(many.code, 0) << many.err;
  EXPECT_NE(many.err.find("note: --checkpoint-every 0.0002 s writes 2000 checkpoints (one every 20 steps), each the "
                          "whole state, at least "),
            std::string::npos)
      << many.err;
  const auto few = run_app({"run", f.case_file.string(), "--out", (f.dir.path() / "few").string(), "--quiet",
                            "--checkpoint-every", "0.02"},
                           f.dir.path());
  ASSERT_EQ(few.code, 0) << few.err;
  EXPECT_EQ(few.err.find("checkpoints (one every"), std::string::npos) << few.err;
}

TEST(CheckpointCli, BadIntervalOrMissingFolderIsAUsageError) {
  Fixture f;
  const fs::path out = f.dir.path() / "out";
  for (const char* bad : {"0", "-1", "abc", "nan"}) {
    const auto r = run_app({"run", f.case_file.string(), "--out", out.string(), "--checkpoint-every", bad}, f.dir.path());
    EXPECT_EQ(r.code, 2) << bad;
    EXPECT_NE(r.err.find("--checkpoint-every"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << "nothing may be written on a usage error";
  }
  const auto missing = run_app({"resume"}, f.dir.path());
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.err.find("missing DIR"), std::string::npos) << missing.err;
  // A case file given for the folder, or a folder that is not there, is
  // named as such (both said "checkpoint file 'X/checkpoint.bin' does not
  // exist (was the run started with --checkpoint-every?)").
  const auto a_file = run_app({"resume", f.case_file.string()}, f.dir.path());
  EXPECT_EQ(a_file.code, 2);
  EXPECT_NE(a_file.err.find("' is not a folder (resume takes the output folder"), std::string::npos) << a_file.err;
  const auto no_folder = run_app({"resume", (f.dir.path() / "nowhere").string()}, f.dir.path());
  EXPECT_EQ(no_folder.code, 2);
  EXPECT_NE(no_folder.err.find("no such folder: '"), std::string::npos) << no_folder.err;
}

}  // namespace

namespace {

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// On a file system without flock a run and its resume go on, each saying
// once that the folder is not locked (and in summary.json's warnings);
// both were refused with exit 3 (tester's probe). ENOLCK is stood in for by
// FQ_TEST_FLOCK_ERRNO (io/folder_lock.h).
TEST(CheckpointCli, RunAndResumeGoOnWithoutLocksWhereTheFileSystemHasNone) {
  Fixture f;
  const fs::path out = f.dir.path() / "out";
  ::setenv("FQ_TEST_FLOCK_ERRNO", std::to_string(ENOLCK).c_str(), 1);
  const int killed = f.run_and_kill(out);
  const auto r = run_app({"resume", out.string(), "--quiet"}, f.dir.path());
  const fs::path once = f.dir.path() / "once";
  const auto whole = run_app({"run", f.case_file.string(), "--out", once.string(), "--quiet"}, f.dir.path());
  ::unsetenv("FQ_TEST_FLOCK_ERRNO");
  ASSERT_EQ(killed, 128 + SIGKILL);
  const std::string warning = "warning: cannot lock output folder '" + out.string() + "': No locks available";
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(count(r.err, warning), 1) << r.err;
  EXPECT_NE(read_text(out / "summary.json").find("going on without the lock"), std::string::npos);
  EXPECT_EQ(whole.code, 0) << whole.err;
  EXPECT_EQ(count(whole.err, "going on without the lock"), 1) << whole.err;
}

}  // namespace
