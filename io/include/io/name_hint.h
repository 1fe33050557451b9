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

// Edit distance between a and b: insertions, deletions, substitutions and
// swaps of two neighbouring letters, each one edit (the optimal string
// alignment distance; a swap is the commonest typing slip).
std::size_t edit_distance(std::string_view a, std::string_view b);

// The name among `names` that `given` most likely meant, or nothing: the
// same name up to case, '_', '-' and spaces ("RK4", "rk_4", "Velocity-Verlet"),
// else the closest after that folding within two edits ("velocity_verlett"),
// one for a name of fewer than six letters ("rk" is "rk4", "ok" is nothing).
std::optional<std::string> nearest_name(std::string_view given, const std::vector<std::string>& names);

// The options ("--name") a command's usage text lists, in order, once each:
// the first word of each line of its option list.
std::vector<std::string> options_in_usage(std::string_view usage);

// The option of `usage` that an unknown option `given` most likely meant:
// nearest_name among them ("--thread" is "--threads"), else the longest
// option the given one begins with ("--output" is "--out"), else the one
// option that begins with the given one ("--integ" is "--integrator"; at
// least three letters after the dashes, and nothing when two do).
std::optional<std::string> nearest_option(std::string_view given, std::string_view usage);

// " (did you mean 'X'?)" for a hint X, "" for none: the one wording of every
// "did you mean" (case-file keys and integrators, command-line options).
std::string did_you_mean(const std::optional<std::string>& hint);

// The message of an unknown option: "unknown option '--given'", followed by
// " (did you mean '--option'?)" when nearest_option finds one.
std::string unknown_option_message(std::string_view given, std::string_view usage);

}  // namespace fq
