// What a run writes and how often (DESIGN.md "Output a user can open").
// Defaults live here only; the case-file reader fills this struct, tests build
// it directly (STYLE.md 3.8). case_def.h includes this header.
#pragma once

#include <filesystem>

namespace fq {

struct OutputDef {
  std::filesystem::path folder;       // output folder OUT/ (case.pvd, frames/, history.csv, ...)
  // 50 frames per simulated second: smooth enough to watch a collapse
  // (members fall ~0.3 m in 0.25 s, i.e. ~12 frames) while a 10 s record
  // stays at 500 files.
  double frame_interval_s = 0.02;     // (s) between .vtu frames
  // 1 kHz: the records in ../shared/data are sampled at 50 Hz (DT = 0.02 s)
  // and time-compressed by at most a few times for the scaled models, so
  // 1 ms rows resolve both the input and the response it drives.
  double history_interval_s = 0.001;  // (s) between history.csv rows
  bool vtk_binary = true;             // appended binary .vtu; false writes ASCII
};

}  // namespace fq
