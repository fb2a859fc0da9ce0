#pragma once
// The one reader of meshtour's JSON documents (scene files, path files, frames manifests, batch
// manifests): strict about types and ranges, and every error names the document and the key
// ("scene.json: 'output.spp' must be between 1 and 4096, got 0"), as pbrt's parameter
// dictionary does, plus a hint on how to fix the document when one is given.
#include <nlohmann/json.hpp>

#include <Eigen/Core>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"

namespace meshtour {

/// The whole of a JSON document's file. \throw IoError naming `what` ("scene file") and the file.
inline std::string read_json_file_text(const std::filesystem::path& file, const std::string& what) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    if (!std::filesystem::exists(file)) throw IoError(file.string() + ": no such file");
    throw IoError("cannot read " + what + " " + file.string() + ": " + std::strerror(errno) + " (check permissions)");
  }
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Parses JSON text. \throw InputError "<source>: not valid JSON: <where and why><hint>".
inline nlohmann::json parse_json_document(const std::string& text, const std::string& source, const std::string& hint = "") {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    // parse_error, and out_of_range for numbers beyond double's range (1e999, found by fuzzing).
    // nlohmann's message carries the line and column.
    std::string what = e.what();
    if (auto pos = what.find("parse error"); pos != std::string::npos) what = what.substr(pos);
    throw InputError(source + ": not valid JSON: " + what + hint);
  }
}

/// Reads one JSON object. Keys are names of its members or dotted paths into nested objects
/// ("cylinder.up"). Optional reads leave their output alone when the key is absent; required
/// reads (number, integer, vector3, ...) fail with "is missing". finish() refuses keys that were
/// never asked for, so that a typo is never silently ignored.
class JsonReader {
public:
  JsonReader(const nlohmann::json& object, std::string source, std::string path = "", std::string hint = "")
      : object_(object), source_(std::move(source)), path_(std::move(path)), hint_(std::move(hint)) {
    if (!object_.is_object()) fail(path_.empty() ? "the document must be a JSON object" : "must be a JSON object");
  }

  bool has(const std::string& key) {
    known_.insert(first_part(key));
    return find(key) != nullptr;
  }
  const nlohmann::json& raw(const std::string& key) {
    known_.insert(first_part(key));
    const nlohmann::json* v = find(key);
    if (!v) fail_key(key, "is missing");
    return *v;
  }
  JsonReader child(const std::string& key) { return JsonReader(raw(key), source_, join(key), hint_); }

  // ---- optional values
  void read(const std::string& key, std::string& out) {
    if (!has(key)) return;
    const auto& v = raw(key);
    if (!v.is_string()) fail_key(key, "must be a string");
    out = v.get<std::string>();
  }
  void read(const std::string& key, double& out, double lo, double hi) {
    if (!has(key)) return;
    out = number_in(key, lo, hi);
  }
  void read(const std::string& key, float& out, double lo, double hi) {
    double d = out;
    read(key, d, lo, hi);
    out = static_cast<float>(d);
  }
  void read(const std::string& key, int& out, int lo, int hi) {
    if (!has(key)) return;
    out = integer(key, lo, hi);
  }
  void read(const std::string& key, bool& out) {
    if (!has(key)) return;
    const auto& v = raw(key);
    if (!v.is_boolean()) fail_key(key, "must be true or false");
    out = v.get<bool>();
  }
  void read_vector(const std::string& key, Eigen::Vector3f& out, double lo, double hi, const std::string& range_message) {
    if (!has(key)) return;
    const auto& v = raw(key);
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
      fail_key(key, "must be an array of three numbers, e.g. [0.8, 0.8, 0.8]");
    for (int k = 0; k < 3; ++k) {
      const double c = v[k].get<double>();
      if (!(c >= lo && c <= hi)) fail_key(key, range_message);
      out[k] = static_cast<float>(c);
    }
  }

  // ---- required values
  double number(const std::string& key) {
    const auto& v = raw(key);
    if (!v.is_number()) fail_key(key, "must be a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail_key(key, "must be finite");
    return d;
  }
  double number_in(const std::string& key, double lo, double hi) {
    const auto& v = raw(key);
    if (!v.is_number()) fail_key(key, "must be a number");
    const double d = v.get<double>();
    if (!(d >= lo && d <= hi)) fail_key(key, "must be between " + number_text(lo) + " and " + number_text(hi) + ", got " + v.dump());
    return d;
  }
  double positive(const std::string& key) {
    const double d = number(key);
    if (!(d > 0.0)) fail_key(key, "must be positive");
    return d;
  }
  int integer(const std::string& key, long long lo, long long hi) {
    const auto& v = raw(key);
    if (!v.is_number_integer()) fail_key(key, "must be a whole number");
    const auto i = v.get<long long>();
    if (i < lo || i > hi) fail_key(key, "must be between " + std::to_string(lo) + " and " + std::to_string(hi) + ", got " + v.dump());
    return static_cast<int>(i);
  }
  Eigen::Vector3d vector3(const std::string& key) {
    const auto& v = raw(key);
    if (!v.is_array() || v.size() != 3) fail_key(key, "must be an array of 3 numbers");
    Eigen::Vector3d out;
    for (int k = 0; k < 3; ++k) {
      if (!v[k].is_number()) fail_key(key, "must be an array of 3 numbers");
      out[k] = v[k].get<double>();
      if (!std::isfinite(out[k])) fail_key(key, "must hold finite numbers");
    }
    return out;
  }
  std::vector<double> numbers(const std::string& key) {
    const auto& v = raw(key);
    if (!v.is_array()) fail_key(key, "must be an array of numbers");
    std::vector<double> out;
    for (const auto& e : v) {
      if (!e.is_number()) fail_key(key, "must be an array of numbers");
      out.push_back(e.get<double>());
      if (!std::isfinite(out.back())) fail_key(key, "must hold finite numbers");
    }
    return out;
  }
  std::vector<std::string> strings(const std::string& key) {
    const auto& v = raw(key);
    if (!v.is_array()) fail_key(key, "must be an array of strings");
    std::vector<std::string> out;
    for (const auto& e : v) {
      if (!e.is_string()) fail_key(key, "must be an array of strings");
      out.push_back(e.get<std::string>());
    }
    return out;
  }

  /// Refuses the keys that were never asked for.
  void finish() const {
    for (const auto& [key, value] : object_.items())
      if (!known_.count(key)) {
        std::string known;
        for (const auto& k : known_) known += (known.empty() ? "" : ", ") + k;
        fail_key(key, "unknown key (known here: " + known + ")");
      }
  }
  [[noreturn]] void fail_key(const std::string& key, const std::string& what) const {
    throw InputError(source_ + ": '" + join(key) + "' " + what + hint_);
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(source_ + (path_.empty() ? ": " : ": '" + path_ + "' ") + what + hint_);
  }

private:
  static std::string first_part(const std::string& key) { return key.substr(0, key.find('.')); }
  std::string join(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  const nlohmann::json* find(const std::string& dotted) const {
    const nlohmann::json* node = &object_;
    std::size_t begin = 0;
    while (begin <= dotted.size()) {
      const std::size_t end = std::min(dotted.find('.', begin), dotted.size());
      const std::string part = dotted.substr(begin, end - begin);
      if (!node->is_object() || !node->contains(part)) return nullptr;
      node = &(*node)[part];
      begin = end + 1;
    }
    return node;
  }
  static std::string number_text(double d) {
    std::ostringstream s;
    s << d;
    return s.str();
  }

  const nlohmann::json& object_;
  std::string source_, path_, hint_;
  std::set<std::string> known_;
};

}  // namespace meshtour
