// Which known name a user probably meant: the "did you mean" of the case
// file's keys and of named choices (integrators) in case files and on the
// command line.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fq {

// Levenshtein distance (insertions, deletions, substitutions) between a and b.
std::size_t edit_distance(std::string_view a, std::string_view b);

// The name among `names` that `given` most likely meant, or nothing: the
// same name up to case, '_', '-' and spaces ("RK4", "rk_4", "Velocity-Verlet"),
// else the closest after that folding within two edits ("velocity_verlett"),
// one for a name of fewer than six letters ("rk" is "rk4", "ok" is nothing).
std::optional<std::string> nearest_name(std::string_view given, const std::vector<std::string>& names);

}  // namespace fq
