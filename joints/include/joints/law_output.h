// What one evaluation of a spring law returns. Shared by every law file so
// that the joint system can treat all laws alike after the per-batch switch.
#pragma once

namespace fq {

struct LawOutput {
  double force_N = 0.0;    // spring force (N), positive in tension (elongation)
  double stored_J = 0.0;   // energy recoverable by elastic unloading (J)
  bool inelastic = false;  // the spring has left its initial elastic range (for the "yielded" event)
  bool failed = false;     // past the ultimate deformation: the spring must be deleted
};

}  // namespace fq
