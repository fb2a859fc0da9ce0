#pragma once
// Numbers in mesh text (OBJ, OFF, ASCII PLY and their headers), private to mesh/: a whole word as
// strtod or strtoll reads it, or false. The common forms go through from_chars (strtod on a copy
// of each word was most of the time of reading a big OBJ); what from_chars does not take ('+',
// hex floats) falls back to strtod, so every file reads as it did.
#include <charconv>
#include <cstdlib>
#include <string>
#include <string_view>
#include <system_error>

namespace meshtour::mesh_text {

inline bool parse_double(std::string_view word, double& value) {
  if (word.empty()) return false;
  const bool plus = word[0] == '+';  // from_chars takes no '+'; after one, no second sign ("+-1" is no number)
  const char* first = word.data() + (plus ? 1 : 0);
  const char* last = word.data() + word.size();
  if (first != last && !(plus && (*first == '-' || *first == '+'))) {
    const auto [end, error] = std::from_chars(first, last, value);
    if (error == std::errc() && end == last) return true;
  }
  const std::string copy(word);
  char* end = nullptr;
  value = std::strtod(copy.c_str(), &end);
  return end == copy.c_str() + copy.size();
}

inline bool parse_integer(std::string_view word, long long& value) {
  if (word.empty()) return false;
  const char* first = word.data() + (word[0] == '+' && word.size() > 1 && word[1] != '-' ? 1 : 0);
  const auto [end, error] = std::from_chars(first, word.data() + word.size(), value);
  return error == std::errc() && end == word.data() + word.size();
}

}  // namespace meshtour::mesh_text
