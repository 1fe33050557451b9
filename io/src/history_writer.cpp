#include "io/history_writer.h"

#include <cerrno>
#include <cmath>
#include <stdexcept>

#include "io/atomic_file.h"

#include "number_format.h"

namespace fq {

HistoryWriter::HistoryWriter() : reference_position_m_(std::make_shared<std::vector<Vec3>>()) {
  add_column("time_s", [](const Simulation& s) { return s.time_s(); });
  add_column("kinetic_J", [](const Simulation& s) { return s.ledger().kinetic_J; });
  add_column("kinetic_rotational_J", [](const Simulation& s) { return s.ledger().kinetic_rotational_J; });
  add_column("gravity_potential_J", [](const Simulation& s) { return s.ledger().gravity_potential_J; });
  add_column("elastic_J", [](const Simulation& s) { return s.ledger().elastic_J; });
  add_column("dissipated_viscous_J", [](const Simulation& s) { return s.ledger().dissipated_viscous_J; });
  add_column("dissipated_plastic_J", [](const Simulation& s) { return s.ledger().dissipated_plastic_J; });
  add_column("dissipated_friction_J", [](const Simulation& s) { return s.ledger().dissipated_friction_J; });
  add_column("work_ground_motion_J", [](const Simulation& s) { return s.ledger().work_ground_motion_J; });
  add_column("energy_balance_error_J", [](const Simulation& s) { return s.ledger().balance_error_J(); });
  // a_g at the row's own time rather than sim.ground_acceleration_mps2(),
  // which is the value of the last force evaluation (one step earlier).
  add_column("ground_accel_x_mps2", [](const Simulation& s) { return s.ground_motion().acceleration(s.time_s()).x(); });
  add_column("ground_accel_y_mps2", [](const Simulation& s) { return s.ground_motion().acceleration(s.time_s()).y(); });
  add_column("ground_accel_z_mps2", [](const Simulation& s) { return s.ground_motion().acceleration(s.time_s()).z(); });
  add_column("max_displacement_m", [ref = reference_position_m_](const Simulation& s) {
    const auto& x = s.bodies().position_m;
    double max_sq = 0.0;
    for (std::size_t i = 0; i < x.size() && i < ref->size(); ++i) max_sq = std::max(max_sq, (x[i] - (*ref)[i]).squaredNorm());
    return std::sqrt(max_sq);
  });
}

HistoryWriter::~HistoryWriter() = default;
HistoryWriter::HistoryWriter(HistoryWriter&&) noexcept = default;
HistoryWriter& HistoryWriter::operator=(HistoryWriter&&) noexcept = default;

void HistoryWriter::add_column(std::string header, HistoryColumn value) {
  if (out_) throw std::logic_error("history column '" + header + "' added after history.csv was opened");
  if (!value) throw std::invalid_argument("history column '" + header + "' has no callback");
  bool chars_ok = !header.empty();
  for (const char c : header)
    chars_ok = chars_ok && ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_');
  const auto underscore = header.rfind('_');
  if (!chars_ok || underscore == std::string::npos || underscore == 0 || underscore + 1 == header.size())
    throw std::invalid_argument("history column '" + header +
                                "': expected name_<unit> made of letters, digits and '_' (e.g. drift_storey1_x_m)");
  for (const std::string& h : headers_)
    if (h == header) throw std::invalid_argument("history column '" + header + "' registered twice");
  headers_.push_back(std::move(header));
  columns_.push_back(std::move(value));
}

void HistoryWriter::open(const std::filesystem::path& file, const Simulation& sim) {
  if (out_) throw std::logic_error("history.csv opened twice");
  *reference_position_m_ = sim.bodies().position_m;
  auto out = std::make_unique<std::ofstream>(file, std::ios::binary | std::ios::trunc);
  if (!*out) throw std::runtime_error("cannot create '" + file.string() + "': " + detail::last_system_error());
  std::string header;
  for (std::size_t c = 0; c < headers_.size(); ++c) {
    if (c > 0) header.push_back(',');
    header += headers_[c];
  }
  header.push_back('\n');
  out->write(header.data(), std::streamsize(header.size()));
  if (!*out) throw std::runtime_error("cannot write '" + file.string() + "'");
  out_ = std::move(out);
  file_ = file;
  rows_ = 0;
  rows_this_process_ = 0;
  bytes_this_process_ = 0;
}

void HistoryWriter::reopen(const std::filesystem::path& file, const std::vector<Vec3>& reference_position_m,
                           std::uint64_t bytes, std::int64_t rows) {
  if (out_) throw std::logic_error("history.csv opened twice");
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec || size < bytes)
    throw std::runtime_error("'" + file.string() + "' is missing or shorter than at the checkpoint (" +
                             std::to_string(bytes) + " bytes expected); the output folder was changed since");
  std::filesystem::resize_file(file, bytes, ec);
  if (ec) throw std::runtime_error("cannot cut '" + file.string() + "' back to the checkpoint: " + ec.message());
  *reference_position_m_ = reference_position_m;
  auto out = std::make_unique<std::ofstream>(file, std::ios::binary | std::ios::app);
  if (!*out) throw std::runtime_error("cannot open '" + file.string() + "' to append");
  out_ = std::move(out);
  file_ = file;
  rows_ = rows;
  rows_this_process_ = 0;
  bytes_this_process_ = 0;
}

std::uint64_t HistoryWriter::bytes_written() const {
  if (!out_) return 0;
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file_, ec);
  if (ec) throw std::runtime_error("cannot read the size of '" + file_.string() + "': " + ec.message());
  return size;
}

void HistoryWriter::write_row(const Simulation& sim) {
  if (!out_) throw std::logic_error("history row written before history.csv was opened");
  line_.clear();
  for (std::size_t c = 0; c < columns_.size(); ++c) {
    if (c > 0) line_.push_back(',');
    detail::append_number(line_, columns_[c](sim));
  }
  line_.push_back('\n');
  out_->write(line_.data(), std::streamsize(line_.size()));
  ++rows_;
  ++rows_this_process_;
  bytes_this_process_ += line_.size();
}

void HistoryWriter::flush() {
  if (!out_) return;
  out_->flush();
  if (!*out_) throw std::runtime_error("cannot write '" + file_.string() + "' (disk full?)");
}

void HistoryWriter::close() {
  if (!out_) return;
  flush();
  // A file system may report a write it could not complete only at close
  // (EIO on NFS, a quota): the rows are then not known to be on disk.
  errno = 0;
  out_->close();
  const bool closed = !out_->fail();
  const std::string why = detail::last_system_error();
  out_.reset();
  if (!closed) throw std::runtime_error("cannot close '" + file_.string() + "': " + why);
}

void HistoryWriter::abandon() noexcept {
  if (!out_) return;
  // The stream's buffer may hold part of a row the disk refused: dropped
  // with the stream (its close may fail again; nothing throws here).
  out_.reset();
  detail::cut_back_to_last_line_end(file_);
  // The rows the file now holds (less its header line).
  const std::int64_t lines = detail::count_line_ends(file_);
  if (lines >= 1) rows_ = lines - 1;
}

bool HistoryWriter::is_open() const { return out_ != nullptr; }

}  // namespace fq
