// "Did you mean": the closest of a command's own words to one it does not know (an option, a command).
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace drape {

// Edits (insert, delete, replace a letter, swap two neighbours) that turn `a` into `b`.
int editDistance(const std::string& a, const std::string& b);

// The candidate nearest to `word`, if it is near enough to be a slip (at most 2 edits, and at most a third of
// the word), else "". Ties go to the first.
std::string closestWord(const std::string& word, const std::vector<std::string>& candidates);

// The first argument that looks like an option (-x, --name, --name=value) and that `command` has not, with
// " (did you mean --frames?)" when one of its options is close: "unknown option --frame (did you mean
// --frames?)". Empty when every option is known.
std::string unknownOptionMessage(const CLI::App& command, const std::vector<std::string>& args);

}  // namespace drape
