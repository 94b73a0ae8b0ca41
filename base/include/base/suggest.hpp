// "Did you mean ...?" for a word the tools do not know: an operation, a symbol, a machine key, a
// command or option, a scene.
//
//   diags.error(loc, fmt::format("unknown operation '{}'{}", word, base::did_you_mean(word, names)));
//   // unknown operation 'fadx'; did you mean 'fadd'?
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nesshi::base {

// The candidate nearest to `word` in edits (a character inserted, deleted or replaced, or two
// neighbours swapped), when near enough to be a slip: one edit for words of three to five
// characters, a third of the word's length beyond; none for shorter words, where one edit is
// anything. Of equally near ones, the nearest in length, then the first.
std::optional<std::string> closest(std::string_view word, const std::vector<std::string>& candidates);

// "; did you mean 'X'?" with the closest candidate, or "" when none is near.
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);

} // namespace nesshi::base
