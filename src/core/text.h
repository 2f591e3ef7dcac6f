// Small text helpers for messages and names: case-insensitive comparison and "did you mean"
// suggestions (shared by the command line and the scene-file checker).
#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace spt {

/// ASCII lower case (names on the command line and in scene files are ASCII).
std::string lowercase(std::string_view s);

/// True when a and b are equal ignoring ASCII case.
bool equal_ignoring_case(std::string_view a, std::string_view b);

/// Levenshtein distance (insertions, deletions and substitutions each cost 1).
std::size_t edit_distance(std::string_view a, std::string_view b);

/// " Did you mean "x"?" when a candidate is close to `word` (edit distance at most
/// max(2, |word|/2), ignoring case), else "".
std::string suggestion(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace spt
