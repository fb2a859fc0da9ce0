#include "options/cli_options.h"

namespace meshtour::options {
namespace {

std::string type_name(const Option& o) {
  switch (o.kind) {
    case Kind::integer: return "INT";
    case Kind::number:
    case Kind::positive: return "NUMBER";
    case Kind::choice:
    case Kind::choice_list:
    case Kind::number_or_choice: return "NAME";
    case Kind::frame_selection: return "FRAMES";
    case Kind::text:
    case Kind::existing_file: return "FILE";
    case Kind::flag: return "";
    case Kind::size: return "WxH";
  }
  return "";
}

CLI::Option* add_one(CLI::App& cmd, Command command, const Option& o, Values& values) {
  const std::string flag(o.flag_in(command));
  // A codec-dependent range is written once, in the row's codec_ranges; the help shows it.
  const std::string help = o.codec_ranges.empty() ? std::string(o.help) : std::string(o.help) + " (" + codec_ranges_text(o) + ")";
  const std::string id(o.id);
  if (o.kind == Kind::flag) {
    CLI::Option* f = cmd.add_flag_callback(flag, [&values, id] { values[id] = "true"; }, help);
    if (!o.group.empty()) f->group(std::string(o.group));
    return f;
  }
  CLI::Option* opt = cmd.add_option_function<std::string>(
      flag, [&values, id, &o](const std::string& text) { values[id] = normalize_value(o, text); }, help);
  opt->check(CLI::Validator([&o](std::string& text) { return check_value(o, text); }, ""));
  opt->type_name(type_name(o));
  if (!o.default_text.empty()) opt->default_str(std::string(o.default_text));
  if (!o.group.empty()) opt->group(std::string(o.group));
  if (o.kind == Kind::existing_file) opt->check(CLI::ExistingFile);
  return opt;
}

void add_rows(CLI::App& cmd, Command command, Values& values, const std::function<bool(const Option&)>& wanted) {
  std::vector<std::pair<const Option*, CLI::Option*>> added;
  for (const Option& o : registry())
    if ((o.commands & command) && wanted(o)) added.emplace_back(&o, add_one(cmd, command, o, values));
  for (const auto& [o, opt] : added) {
    if (o->excludes.empty()) continue;
    for (const auto& [other, other_opt] : added)
      if (other->id == o->excludes) opt->excludes(other_opt);
  }
}

}  // namespace

void add_registered_options(CLI::App& cmd, Command command, Values& values) {
  add_rows(cmd, command, values, [](const Option&) { return true; });
}

void add_registered_options(CLI::App& cmd, Command command, Values& values, std::initializer_list<std::string_view> ids) {
  const std::vector<std::string_view> list(ids);
  add_rows(cmd, command, values, [&list](const Option& o) { return std::find(list.begin(), list.end(), o.id) != list.end(); });
}

}  // namespace meshtour::options
