#pragma once
// The option registry: every setting a user can give meshtour is one row of one table
// (option_registry.cpp), and everything that knows about settings is derived from that table:
// the command-line options of every command (options/cli_options.h), the scene-file keys (the
// scene-file reader, scenes/scene.cpp, reads the row's scene_key), the batch-manifest columns
// (options/batch_manifest.cpp), the arguments a farm passes to its tasks (forwarded_args) and
// docs/OPTIONS.md (options_markdown).
//
// A row holds the option's name, type, range, help, scene-file key and manifest column; nothing
// else in the sources repeats them. Text is checked by check_value() wherever it comes from, so a
// value is accepted or refused the same way on the command line, in a scene file and in a
// manifest, and it is parsed once, at that edge, into the typed field of a library's settings:
// a setting of the tour by the scene's binding table (scenes/scene_options.h), the video's poster
// and caption by cli/video_settings.h, a command's own setting by the binding its command gives
// the row (options::add_command_options, options/cli_options.h). Nothing below cli/ and these
// readers sees an option's text.
//
// Adding an option = one row in option_registry.cpp plus its binding: one options::to(field) in
// the command that takes it, or one entry of the scene's binding table for a tour setting.
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace meshtour::options {

/// The commands that take options (a bit set in Option::commands).
enum Command : unsigned {
  tour = 1u << 0,
  render = 1u << 1,
  batch = 1u << 2,
  farm = 1u << 3,
  path = 1u << 4,
  evaluate = 1u << 5,
  encode = 1u << 6,
  info = 1u << 7,
};

/// Where a farm must pass an option given to `farm slurm` (a bit set in Option::farm).
enum FarmPass : unsigned {
  not_passed = 0,
  render_tasks = 1u << 0,  ///< each `meshtour render` array task (it changes pixels or the path)
  encode_job = 1u << 1,    ///< the dependent `meshtour encode` job
  batch_tasks = 1u << 2,   ///< each `meshtour batch --item` array task
};

enum class Kind {
  integer,           ///< whole number in [lo, hi]
  number,            ///< real number in [lo, hi]
  positive,          ///< real number > 0 (lo, hi unused)
  choice,            ///< one of `choices`
  choice_list,       ///< comma-separated subset of `choices`
  number_or_choice,  ///< a number in [lo, hi] or one of `choices` (e.g. --fov auto)
  frame_selection,   ///< jobs/frame_range.h syntax
  text,              ///< free text (a file name)
  existing_file,     ///< a file that must exist
  flag,              ///< present or not ("true")
  size,              ///< WIDTHxHEIGHT in pixels, each in [lo, hi] (and even with even_sides; e.g. --poster-size 640x360)
  memory_size,       ///< a number of bytes with an optional unit: 512M, 8G, 1.5T (core/memory_size.h)
  up_direction,      ///< an axis, a vector such as 0,1,0.2, longest-aabb, pca or auto (pathgen/cylinder.h)
};

/// What a row means in some commands, where it differs from the row's own help and default (e.g.
/// `path`'s --up also takes a vector, and its --path defaults to the paper method).
struct CommandMeaning {
  unsigned commands = 0;           ///< Command bits
  std::string_view help;           ///< "" = the row's
  std::string_view default_text;   ///< "" = the row's
  std::optional<Kind> kind;        ///< unset = the row's
};

struct Option {
  std::string_view id;    ///< the concept's name (Values key), e.g. "frame-count"
  std::string_view flag;  ///< command-line name, e.g. "--frames"
  Kind kind;
  std::string_view short_flag;  ///< one-letter name, e.g. "-o" ("" = none)
  std::string_view type_name;   ///< placeholder in --help (FILE, DIR, PNG); "" = the kind's
  double lo = 0, hi = 0;
  std::vector<std::string_view> choices;
  bool ignore_case = false;
  std::string_view default_text;  ///< shown in help and docs ("" = none / computed)
  std::string_view help;          ///< one line (may wrap with \n in --help)
  std::string_view long_help;     ///< extra paragraph for docs/OPTIONS.md ("" = none)
  std::string_view scene_key;     ///< scene-file key path, e.g. "output.spp" ("" = not in scene files)
  bool manifest_column = false;   ///< a batch-manifest column (named id)
  unsigned commands = 0;          ///< Command bits
  unsigned farm = not_passed;     ///< FarmPass bits
  std::string_view group;         ///< help group ("" = the command's options)
  /// Commands that spell the flag differently (e.g. render's tour length is --frame-count,
  /// because its --frames selects frames).
  std::string_view alt_flag;
  unsigned alt_flag_commands = 0;
  /// Ids of the options that cannot be given together with this one, comma-separated ("width,height").
  std::string_view excludes;
  /// The range is the video codec's (CRF: encoder/video_codecs.h); lo..hi is the widest of them.
  bool codec_dependent = false;
  bool even_sides = false;          ///< Kind::size: both sides even (video chroma subsampling)
  unsigned required = 0;            ///< Command bits of the commands that need it
  std::vector<CommandMeaning> meanings;  ///< per-command help, default or kind

  /// Whether `id` is one of the options this one excludes.
  bool excludes_option(std::string_view id) const {
    for (std::string_view rest = excludes; !rest.empty();) {
      const std::size_t comma = rest.find(',');
      if (rest.substr(0, comma) == id) return true;
      rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
    }
    return false;
  }
  /// The flag this option has in `command`.
  std::string_view flag_in(Command command) const { return (alt_flag_commands & command) ? alt_flag : flag; }
  /// The help, default and kind of the option in `command`.
  std::string_view help_in(Command command) const;
  std::string_view default_in(Command command) const;
  Kind kind_in(Command command) const;
};

/// Every row, in the order values are applied (so that e.g. --seconds sees the final --fps).
const std::vector<Option>& registry();
/// The row of `id`. \throw std::logic_error for an unknown id (a programming error).
const Option& option(std::string_view id);
/// The row whose scene_key is `key`, or nullptr.
const Option* option_for_scene_key(std::string_view key);

/// Checks `text` against the row: "" when valid, else what is wrong ("must be between 1 and 4096,
/// got 0"), without the option's name (each reader adds its own context).
std::string check_value(const Option& o, const std::string& text);
/// The same for the row's meaning in `command` (path's --up takes vectors too).
std::string check_value(const Option& o, const std::string& text, Command command);
/// The canonical text of a valid value (lower case where case is ignored, lists without blanks).
std::string normalize_value(const Option& o, const std::string& text);
/// check_value, and for a codec-dependent option also the codec's own range ("must be between 0
/// and 51 for h264, got 60").
std::string check_value_for_codec(const Option& o, const std::string& text, std::string_view codec);
/// "h264 0..51, default 18; vp9 0..63, default 31" for a codec-dependent option ("" otherwise).
std::string codec_ranges_text(const Option& o);

/// Values given for a set of options: id -> canonical text. Only what the user gave.
using Values = std::map<std::string, std::string, std::less<>>;

/// Where a row's value goes: the tour's Scene (its camera, timing and render settings; scene keys
/// and the tour length), the path search's options (PaperPathOptions; scene keys "patches.*" and
/// "paper.*"), the video's deliverables (poster, caption, title card: manifest columns without a
/// scene key), or only the command that takes it (bound with options::bind()).
enum class Target { scene, path_search, video, command };
Target target(const Option& o);

/// Reads "WIDTHxHEIGHT" (e.g. "640x360"; 'x' or 'X', no blanks, no sign): true and the two numbers,
/// or false when the text is not of that form. The range is the row's (check_value).
bool parse_pixel_size(std::string_view text, int& width, int& height);

/// The registry's text form of a number (shortest text that reads back to the same double).
std::string number_text(double value);

/// Command-line arguments that give `values` to `command` again (--flag text ...), for the rows
/// whose FarmPass includes `pass` and that `command` takes. Deterministic order (the registry's).
std::vector<std::string> forwarded_args(const Values& values, FarmPass pass, Command command);

/// docs/OPTIONS.md: every option with its commands, type, range, default, scene key and column.
std::string options_markdown();

/// The name of a command bit ("tour").
std::string_view command_name(Command c);
/// Every command, in help order.
inline constexpr Command kAllCommands[] = {tour, render, batch, farm, path, evaluate, encode, info};

/// For a flag that the command `command` (its name, e.g. "tour") does not take: what the registry
/// knows about it, e.g. "tour takes the frame count as --frames (--frame-count is render's name)"
/// or "--out-dir is an option of render, batch and farm, not of tour"; "" when no row has it.
std::string misplaced_flag_hint(std::string_view command, std::string_view flag);

}  // namespace meshtour::options
