// Private to io: events.csv, one row per fq::Event (STYLE.md 3.4 "record each
// break with who, when, where and why"):
//   time_s,step,kind,joint_id,body_a,body_b,spring_index,mode,force_N,x_m,y_m,z_m,body_a_name,body_b_name,
//   node,joint_name
// Rows are appended as the log grows (at each history sample), so the file
// follows the run; -1 marks "not applicable" ids as in fq::Event, and an
// empty name a body id that is -1. The names (the members' ids in the case
// file) are there so that a weak point can be read without the VTK frames
// (workflow probe: only numbers, the names only in body_names of a frame).
// node and joint_name (the joint's node id and its name, "node:member_a-
// member_b", io/joint_builder.h; empty for a joint id of -1) name the joint
// itself: a joint id is its place in the case's joint order and changes from
// case to case (retrofit probe: joint 13 was another joint in frames B and
// C), and the two body names do not say at which node the joint is. They
// come last so that the earlier columns keep their places.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "dem_core/events.h"

namespace fq::detail {

class EventCsvWriter {
 public:
  void open(const std::filesystem::path& file);
  // Continues `file` (checkpoint resume): cut back to `bytes`, appended from
  // there; the first `written` entries of the log are in it, as `rows` rows.
  void reopen(const std::filesystem::path& file, std::uint64_t bytes, std::size_t written, std::int64_t rows);
  std::size_t written() const { return written_; }
  // Bytes in the file after a flush().
  std::uint64_t bytes_written() const;
  // Writes the events of `log` not written yet.
  void write_new(const EventLog& log);
  // The bodies' names, by id, for the name columns (before the first write).
  void set_body_names(std::vector<std::string> names) { body_names_ = std::move(names); }
  // The joints' node ids and names, by joint id, for the node and joint_name
  // columns (before the first write; the same length).
  void set_joint_names(std::vector<std::string> nodes, std::vector<std::string> names) {
    joint_nodes_ = std::move(nodes);
    joint_names_ = std::move(names);
    if (joint_nodes_.size() != joint_names_.size()) joint_nodes_.resize(joint_names_.size());
  }
  void flush();
  void close();
  // As HistoryWriter::abandon: closed, cut back to its last complete row.
  void abandon() noexcept;
  std::int64_t rows() const { return rows_; }

 private:
  std::unique_ptr<std::ofstream> out_;
  std::filesystem::path file_;
  std::size_t written_ = 0;  // entries of the log already in the file
  std::int64_t rows_ = 0;
  std::vector<std::string> body_names_;
  std::vector<std::string> joint_nodes_, joint_names_;
  std::string line_;
};

}  // namespace fq::detail
