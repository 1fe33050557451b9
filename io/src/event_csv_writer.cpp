#include "event_csv_writer.h"

#include <cerrno>
#include <stdexcept>
#include <string>
#include <string_view>

#include "io/atomic_file.h"
#include "io/csv_text.h"

#include "number_format.h"

namespace fq::detail {

namespace {
constexpr std::string_view kHeader =
    "time_s,step,kind,joint_id,body_a,body_b,spring_index,mode,force_N,x_m,y_m,z_m,body_a_name,body_b_name,node,"
    "joint_name";
}  // namespace

void EventCsvWriter::open(const std::filesystem::path& file) {
  auto out = std::make_unique<std::ofstream>(file, std::ios::binary | std::ios::trunc);
  if (!*out) throw std::runtime_error("cannot create '" + file.string() + "': " + last_system_error());
  *out << kHeader << '\n';
  if (!*out) throw std::runtime_error("cannot write '" + file.string() + "'");
  out_ = std::move(out);
  file_ = file;
  written_ = 0;
  rows_ = 0;
}

void EventCsvWriter::reopen(const std::filesystem::path& file, std::uint64_t bytes, std::size_t written,
                            std::int64_t rows) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec || size < bytes)
    throw std::runtime_error("'" + file.string() + "' is missing or shorter than at the checkpoint (" +
                             std::to_string(bytes) + " bytes expected); the output folder was changed since");
  {
    // A run begun by a framequake that wrote other columns (before node
    // and joint_name) would get rows that do not match its header.
    std::ifstream in(file, std::ios::binary);
    std::string header;
    std::getline(in, header);
    if (header != kHeader)
      throw std::runtime_error("'" + file.string() + "' has the columns of another framequake version (" +
                               header.substr(0, 200) + "; this one writes " + std::string(kHeader) +
                               "): resume the run with the framequake that started it");
  }
  std::filesystem::resize_file(file, bytes, ec);
  if (ec) throw std::runtime_error("cannot cut '" + file.string() + "' back to the checkpoint: " + ec.message());
  auto out = std::make_unique<std::ofstream>(file, std::ios::binary | std::ios::app);
  if (!*out) throw std::runtime_error("cannot open '" + file.string() + "' to append");
  out_ = std::move(out);
  file_ = file;
  written_ = written;
  rows_ = rows;
}

std::uint64_t EventCsvWriter::bytes_written() const {
  if (!out_) return 0;
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file_, ec);
  if (ec) throw std::runtime_error("cannot read the size of '" + file_.string() + "': " + ec.message());
  return size;
}

void EventCsvWriter::write_new(const EventLog& log) {
  if (!out_) return;
  const auto& all = log.all();
  if (all.size() < written_) written_ = 0;  // the log was cleared: what follows is new
  for (; written_ < all.size(); ++written_) {
    const Event& e = all[written_];
    line_.clear();
    append_number(line_, e.time_s);
    line_.push_back(',');
    append_integer(line_, e.step);
    line_.push_back(',');
    line_ += event_kind_name(e.kind);
    line_.push_back(',');
    append_integer(line_, e.joint_id);
    line_.push_back(',');
    append_integer(line_, e.body_a);
    line_.push_back(',');
    append_integer(line_, e.body_b);
    line_.push_back(',');
    append_integer(line_, e.spring_index);
    line_.push_back(',');
    line_ += csv_text(e.mode ? e.mode : "");
    line_.push_back(',');
    append_number(line_, e.force_N);
    for (int k = 0; k < 3; ++k) {
      line_.push_back(',');
      append_number(line_, e.position_m[k]);
    }
    for (const BodyId b : {e.body_a, e.body_b}) {
      line_.push_back(',');
      if (b >= 0 && std::size_t(b) < body_names_.size()) line_ += csv_text(body_names_[std::size_t(b)]);
    }
    const bool named = e.joint_id >= 0 && std::size_t(e.joint_id) < joint_names_.size();
    line_.push_back(',');
    if (named) line_ += csv_text(joint_nodes_[std::size_t(e.joint_id)]);
    line_.push_back(',');
    if (named) line_ += csv_text(joint_names_[std::size_t(e.joint_id)]);
    line_.push_back('\n');
    out_->write(line_.data(), std::streamsize(line_.size()));
    ++rows_;
  }
}

void EventCsvWriter::flush() {
  if (!out_) return;
  out_->flush();
  if (!*out_) throw std::runtime_error("cannot write '" + file_.string() + "' (disk full?)");
}

void EventCsvWriter::close() {
  if (!out_) return;
  flush();
  // A file system may report a write it could not complete only at close
  // (EIO on NFS, a quota): the rows are then not known to be on disk.
  errno = 0;
  out_->close();
  const bool closed = !out_->fail();
  const std::string why = last_system_error();
  out_.reset();
  if (!closed) throw std::runtime_error("cannot close '" + file_.string() + "': " + why);
}

void EventCsvWriter::abandon() noexcept {
  if (!out_) return;
  // The stream's buffer may hold part of a row the disk refused: dropped
  // with the stream (its close may fail again; nothing throws here).
  out_.reset();
  cut_back_to_last_line_end(file_);
  // The rows the file now holds (less its header line).
  const std::int64_t lines = count_line_ends(file_);
  if (lines >= 1) rows_ = lines - 1;
}

}  // namespace fq::detail
