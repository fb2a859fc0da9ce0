#include "options/cli_options.h"

#include <stdexcept>

namespace meshtour::options {
namespace {

std::string type_name(const Option& o, Kind kind) {
  if (!o.type_name.empty()) return std::string(o.type_name);
  switch (kind) {
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
    case Kind::memory_size: return "SIZE";
    case Kind::up_direction: return "AXIS";
  }
  return "";
}

CLI::Option* add_one(CLI::App& cmd, Command command, const Option& o, const Binding& take) {
  const std::string names = o.short_flag.empty() ? std::string(o.flag_in(command))
                                                 : std::string(o.short_flag) + "," + std::string(o.flag_in(command));
  // A codec-dependent range is written once, in the encoder's codec table (encoder/video_codecs.h); the help shows it.
  const std::string help = !o.codec_dependent ? std::string(o.help_in(command))
                                              : std::string(o.help_in(command)) + " (" + codec_ranges_text(o) + ")";
  const Kind kind = o.kind_in(command);
  CLI::Option* opt = nullptr;
  if (kind == Kind::flag) {
    opt = cmd.add_flag_callback(names, [take] { take("true"); }, help);
  } else {
    opt = cmd.add_option_function<std::string>(
        names, [take, &o](const std::string& text) { take(normalize_value(o, text)); }, help);
    opt->check(CLI::Validator([&o, command](std::string& text) { return check_value(o, text, command); }, ""));
    opt->type_name(type_name(o, kind));
    if (const std::string_view d = o.default_in(command); !d.empty()) opt->default_str(std::string(d));
    if (kind == Kind::existing_file) opt->check(CLI::ExistingFile);
  }
  if (!o.group.empty()) opt->group(std::string(o.group));
  if (o.required & command) opt->required();
  return opt;
}

void add_rows(CLI::App& cmd, Command command, Values& values, const Bindings* bound) {
  std::vector<std::pair<const Option*, CLI::Option*>> added;
  for (const Option& o : registry()) {
    if (!(o.commands & command)) continue;
    Binding take;
    if (bound) {
      if (const auto it = bound->find(o.id); it != bound->end()) take = it->second;
      else if (target(o) == Target::command)
        throw std::logic_error("meshtour: " + std::string(command_name(command)) + " takes " + std::string(o.flag_in(command)) +
                               " but binds it to nothing");
    }
    if (!take) take = [&values, id = std::string(o.id)](const std::string& text) { values[id] = text; };
    added.emplace_back(&o, add_one(cmd, command, o, take));
  }
  for (const auto& [o, opt] : added) {
    if (o->excludes.empty()) continue;
    for (const auto& [other, other_opt] : added)
      if (o->excludes_option(other->id)) opt->excludes(other_opt);
  }
}

}  // namespace

void add_command_options(CLI::App& cmd, Command command, Values& values, const Bindings& bound) {
  add_rows(cmd, command, values, &bound);
}

void add_registered_options(CLI::App& cmd, Command command, Values& values) { add_rows(cmd, command, values, nullptr); }

}  // namespace meshtour::options
