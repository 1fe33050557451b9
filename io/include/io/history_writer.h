// history.csv: one row per history sample, time in the first column and the
// unit in every header (DESIGN.md "Conventions"), in the format the
// validation comparator reads (STYLE.md 3.9).
//
// Columns are named callbacks evaluated at each sample, so later issues add
// theirs (drift per storey and direction, base shear) with add_column()
// before the file is opened. The standard columns, in order:
//   time_s                     t of the current poses, sim.time_s()
//   kinetic_J                  translational + rotational kinetic energy
//   kinetic_rotational_J       the rotational part of kinetic_J
//   gravity_potential_J, elastic_J, dissipated_viscous_J, dissipated_plastic_J,
//   dissipated_friction_J, work_ground_motion_J, energy_balance_error_J
//                              the energy ledger (dem_core/energy_ledger.h)
//   ground_accel_{x,y,z}_mps2  a_g(t) evaluated at the row's time
//   max_displacement_m         largest |x_i(t) - x_i(0)| over the bodies
//                              (relative frame: displacement relative to the ground)
// Time convention: observers run after step n, so poses (and time_s) are at
// t_{n+1}. With central difference (the default) the ledger is the one of
// step n, one dt earlier (its kinetic energy needs v(n+1/2)); at the default
// 1 ms row interval and dt ~ 1e-5 s that offset is 1 % of a row. The other
// integrators hold velocities at the poses' time, and their ledger is at
// the row's time.
//
// Values are printed in their shortest round-trip form (bitwise what the
// engine held). Rows go to a buffered stream; flush() (called at every frame)
// bounds what a crash can lose.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dem_core/simulation.h"

namespace fq {

using HistoryColumn = std::function<double(const Simulation& sim)>;

class HistoryWriter {
 public:
  HistoryWriter();  // registers the standard columns
  ~HistoryWriter();
  HistoryWriter(HistoryWriter&&) noexcept;
  HistoryWriter& operator=(HistoryWriter&&) noexcept;

  // `header` is name_<unit> (units as in the code: m, s, J, N, Nm, mps,
  // mps2, rad, radps, kg; "ratio" for dimensionless), unique, letters,
  // digits and '_' only. The form is checked, the unit word is not: throws
  // std::invalid_argument, or std::logic_error once the file is open.
  void add_column(std::string header, HistoryColumn value);
  const std::vector<std::string>& headers() const { return headers_; }

  // Creates `file`, writes the header line and takes the bodies' current
  // positions as the reference for max_displacement_m.
  void open(const std::filesystem::path& file, const Simulation& sim);
  // Continues `file` as written by an earlier part of the same run
  // (checkpoint resume): cuts it back to its first `bytes` bytes, appends
  // from there, counts rows from `rows`; `reference_position_m` are the
  // bodies' positions at t = 0 (for max_displacement_m). Throws
  // std::runtime_error naming the file when it is shorter than `bytes`.
  void reopen(const std::filesystem::path& file, const std::vector<Vec3>& reference_position_m, std::uint64_t bytes,
              std::int64_t rows);
  // Bytes in the file after a flush().
  std::uint64_t bytes_written() const;
  void write_row(const Simulation& sim);
  void flush();
  void close();
  // After a failed write (OutputError during a run): closes the file without
  // asking more of the disk and cuts it back to its last complete row.
  // Never throws.
  void abandon() noexcept;
  bool is_open() const;
  std::int64_t rows() const { return rows_; }
  // Rows written since open() or reopen(), and their mean length (bytes,
  // newlines included; 0 before one).
  std::int64_t rows_this_process() const { return rows_this_process_; }
  double mean_row_bytes() const {
    return rows_this_process_ > 0 ? double(bytes_this_process_) / double(rows_this_process_) : 0.0;
  }

 private:
  std::vector<std::string> headers_;
  std::vector<HistoryColumn> columns_;
  std::shared_ptr<std::vector<Vec3>> reference_position_m_;  // shared with the displacement column
  std::unique_ptr<std::ofstream> out_;
  std::filesystem::path file_;
  std::string line_;  // reused row buffer
  std::int64_t rows_ = 0;
  std::int64_t rows_this_process_ = 0;
  std::uint64_t bytes_this_process_ = 0;
};

}  // namespace fq
