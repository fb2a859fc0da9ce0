#include "options/batch_manifest.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/json_reader.h"

namespace meshtour {
namespace {

// A column is "mesh", "output" or a registry row marked as a manifest column, named by its id; the
// tour length's id is "frame-count", and "frames" (its flag) names it too.
const options::Option* column_option(const std::string& key) {
  const std::string id = key == "frames" ? "frame-count" : key;
  for (const options::Option& o : options::registry())
    if (o.manifest_column && o.id == id) return &o;
  return nullptr;
}

bool known_column(const std::string& key) { return key == "mesh" || key == "output" || column_option(key) != nullptr; }

std::string column_list() {
  std::string list = "mesh, output";
  for (const options::Option& o : options::registry())
    if (o.manifest_column) list += ", " + std::string(o.id == "frame-count" ? "frames" : o.id);
  return list;
}

std::string trim(std::string s) {
  const auto space = [](unsigned char c) { return std::isspace(c) != 0; };
  s.erase(s.begin(), std::find_if_not(s.begin(), s.end(), space));
  s.erase(std::find_if_not(s.rbegin(), s.rend(), space).base(), s.end());
  return s;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// One CSV record: comma-separated, fields optionally in double quotes ("" inside is a quote).
std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        fields.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  for (auto& f : fields) f = trim(f);
  return fields;
}

// Sets one field of `item` from text; a bad value becomes the item's error.
void set_field(BatchItem& item, const std::string& key, const std::string& value, const std::filesystem::path& base) {
  if (value.empty() || !item.error.empty()) return;
  if (key == "mesh") {
    const std::filesystem::path p(value);
    item.mesh = p.is_absolute() ? p : base / p;
  } else if (key == "output") {
    item.output = value;
  } else if (const options::Option* o = column_option(key)) {
    // Checked by the row, as on the command line; a tour's video is H.264.
    const std::string problem = options::check_value_for_codec(*o, value, "h264");
    if (!problem.empty()) item.error = key + (problem.starts_with("'") ? " " : " '" + value + "': ") + problem;
    else item.values[std::string(o->id)] = options::normalize_value(*o, value);
  }
}

// Defaults and checks that need the whole item: mesh given, output name, unique outputs.
void finish_items(std::vector<BatchItem>& items) {
  std::map<std::string, int> outputs;
  for (auto& item : items) {
    if (item.error.empty() && item.mesh.empty()) item.error = "no mesh given";
    if (item.output.empty() && !item.mesh.empty()) {
      std::string stem = item.mesh.stem().string();
      if (lower(item.mesh.extension().string()) == ".json" && lower(stem).ends_with(".svx")) stem.resize(stem.size() - 4);  // bell.svx.json
      item.output = stem + ".mp4";
    }
    if (item.error.empty()) {
      const std::filesystem::path out(item.output);
      if (out.has_parent_path() || out.is_absolute()) item.error = "output '" + item.output + "' must be a plain file name (it goes into --out-dir)";
      else if (out.extension() != ".mp4") item.error = "output '" + item.output + "' must end in .mp4";
    }
    if (const auto poster = item.values.find("poster"); item.error.empty() && poster != item.values.end()) {
      const std::filesystem::path p(poster->second);
      if (p.has_parent_path() || p.is_absolute()) item.error = "poster '" + poster->second + "' must be a plain file name (it goes into --out-dir)";
      else if (p.extension() != ".png") item.error = "poster '" + poster->second + "' must end in .png";
    }
    if (item.error.empty()) {
      const auto [it, inserted] = outputs.emplace(item.output, item.index);
      if (!inserted) item.error = "output '" + item.output + "' is already used by item " + std::to_string(it->second);
    }
  }
}


std::vector<BatchItem> read_csv(const std::filesystem::path& file, const std::string& text) {
  const std::filesystem::path base = file.parent_path();
  std::istringstream in(text);
  std::string line;
  std::vector<std::string> header;
  std::vector<BatchItem> items;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (trim(line).empty() || trim(line)[0] == '#') continue;
    auto fields = split_csv(line);
    if (header.empty()) {
      for (auto& f : fields) {
        f = lower(f);
        if (!known_column(f))
          throw InputError(file.string() + ":" + std::to_string(line_no) + ": unknown column '" + f +
                           "' in the header row (columns: " + column_list() + ")");
      }
      if (std::find(fields.begin(), fields.end(), "mesh") == fields.end())
        throw InputError(file.string() + ":" + std::to_string(line_no) + ": the header row has no 'mesh' column");
      header = fields;
      continue;
    }
    BatchItem item;
    item.index = static_cast<int>(items.size());
    item.line = line_no;
    if (fields.size() > header.size())
      item.error = "line has " + std::to_string(fields.size()) + " fields, the header " + std::to_string(header.size());
    for (std::size_t c = 0; c < fields.size() && c < header.size(); ++c) set_field(item, header[c], fields[c], base);
    items.push_back(std::move(item));
  }
  if (header.empty()) throw InputError(file.string() + ": empty batch manifest (expected a header row such as 'mesh,up,output')");
  return items;
}

std::vector<BatchItem> read_json(const std::filesystem::path& file, const std::string& text) {
  const std::filesystem::path base = file.parent_path();
  // Parsed by the one JSON reader; each item's keys are then checked by the registry, and a bad
  // one makes only its item bad.
  nlohmann::json j = parse_json_document(text, file.string());
  if (j.is_object() && j.contains("items")) j = j["items"];
  if (!j.is_array()) throw InputError(file.string() + ": expected an array of items, or an object with an \"items\" array");
  std::vector<BatchItem> items;
  for (const auto& entry : j) {
    BatchItem item;
    item.index = static_cast<int>(items.size());
    item.line = item.index + 1;
    if (!entry.is_object()) {
      item.error = "item is not a JSON object";
    } else {
      for (const auto& [key, value] : entry.items()) {
        if (!known_column(key)) {
          if (item.error.empty()) item.error = "unknown key '" + key + "'";
          continue;
        }
        std::string v;
        if (value.is_string()) v = value.get<std::string>();
        else if (value.is_number_integer()) v = std::to_string(value.get<long long>());
        else if (value.is_number()) v = options::number_text(value.get<double>());
        else if (value.is_boolean()) v = value.get<bool>() ? "true" : "false";
        else if (item.error.empty()) item.error = "'" + key + "' must be a string or a number";
        set_field(item, key, v, base);
      }
    }
    items.push_back(std::move(item));
  }
  return items;
}

}  // namespace

std::vector<BatchItem> read_batch_manifest(const std::filesystem::path& file) {
  const std::string text = read_json_file_text(file, "batch manifest");
  const std::string ext = lower(file.extension().string());
  std::vector<BatchItem> items;
  if (ext == ".json") items = read_json(file, text);
  else if (ext == ".csv") items = read_csv(file, text);
  else throw InputError(file.string() + ": a batch manifest is .csv (with a header row) or .json");
  if (items.empty()) throw InputError(file.string() + ": the batch manifest lists no items");
  finish_items(items);
  return items;
}

}  // namespace meshtour
