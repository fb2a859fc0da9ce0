#pragma once
// Reading mesh text (OBJ, OFF, ASCII STL, ASCII PLY and their headers), private to mesh/.
//
// Numbers: a whole word as strtod or strtoll reads it, or false. The common forms go through from_chars (strtod on a copy
// of each word was most of the time of reading a big OBJ); what from_chars does not take ('+',
// hex floats) falls back to strtod, so every file reads as it did.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

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

// Lines: the file's lines through a buffer of its own (a getline and a string stream per line was
// most of the time of reading a big OBJ). A line longer than the buffer grows it.
class LineReader {
public:
  explicit LineReader(const std::filesystem::path& file) : in_(file, std::ios::binary), buffer_(buffer_size(file)) {}

  // The next line without its end ("\n" or "\r\n"); false at the end of the file.
  bool next(std::string_view& line) {
    for (;;) {
      if (const void* found = std::memchr(buffer_.data() + at_, '\n', end_ - at_)) {
        const auto stop = static_cast<std::size_t>(static_cast<const char*>(found) - buffer_.data());
        line = std::string_view(buffer_.data() + at_, stop - at_);
        at_ = stop + 1;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        return true;
      }
      if (!in_) {  // the last line, without an end
        if (at_ == end_) return false;
        line = std::string_view(buffer_.data() + at_, end_ - at_);
        at_ = end_;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        return true;
      }
      std::memmove(buffer_.data(), buffer_.data() + at_, end_ - at_);
      end_ -= at_;
      at_ = 0;
      if (end_ == buffer_.size()) buffer_.resize(2 * buffer_.size());
      in_.read(buffer_.data() + end_, static_cast<std::streamsize>(buffer_.size() - end_));
      end_ += static_cast<std::size_t>(in_.gcount());
    }
  }

private:
  // 1 MiB, or the whole file where it is smaller: zeroing 1 MiB per small file was most of the
  // cost of reading one (and of each of the mesh fuzzer's inputs).
  static std::size_t buffer_size(const std::filesystem::path& file) {
    constexpr std::size_t kLargest = std::size_t{1} << 20, kSmallest = 4096;
    std::error_code error;
    const std::uintmax_t size = std::filesystem::file_size(file, error);
    if (error || size >= kLargest) return kLargest;
    return std::max(kSmallest, static_cast<std::size_t>(size) + 1);
  }

  std::ifstream in_;
  std::vector<char> buffer_;
  std::size_t at_ = 0, end_ = 0;
};

inline bool blank(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

// The line's whitespace-separated words, into `words` (reused: no allocation per line).
inline void split_words(std::string_view line, std::vector<std::string_view>& words) {
  words.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && blank(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !blank(line[i])) ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
}

}  // namespace meshtour::mesh_text
