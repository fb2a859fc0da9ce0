// The option registry is the one description of every setting: these tests walk its rows and
// check that each one means the same thing on the command line, in a scene file, in a batch
// manifest and in the arguments a farm passes to its tasks, with its range enforced alike.
#include <gtest/gtest.h>

#include <CLI/CLI.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "core/error.h"
#include "core/frame_sizes.h"
#include "helpers.h"
#include "options/batch_manifest.h"
#include "options/cli_options.h"
#include "options/option_registry.h"
#include "tracer/environment.h"
#include "evaluate/evaluate.h"
#include "pathgen/feature_orbit.h"
#include "scenes/scene.h"
#include "scenes/scene_options.h"

namespace meshtour {
namespace {

using options::Kind;
using options::Option;

const options::Command kCommands[] = {options::tour,  options::render,   options::batch, options::farm,
                                      options::path,  options::evaluate, options::encode};

// A valid value of the row that is not its default (so that applying it shows).
std::string sample_value(const Option& o) {
  // A number inside the range, or another one when that is the default.
  const auto number_not_default = [&o](double first, double second) {
    const std::string text = options::number_text(first);
    return text == o.default_text ? options::number_text(second) : text;
  };
  switch (o.kind) {
    case Kind::integer: return number_not_default(o.lo + (o.hi > o.lo ? 1 : 0), o.lo);
    case Kind::number: return number_not_default(o.lo + 0.25 * (o.hi - o.lo), o.lo + 0.75 * (o.hi - o.lo));
    case Kind::positive: return "0.0025";
    case Kind::choice:  // the last choice that is not the default
      for (auto c = o.choices.rbegin(); c != o.choices.rend(); ++c)
        if (*c != o.default_text) return std::string(*c);
      return std::string(o.choices.back());
    case Kind::choice_list: return std::string(o.choices.front()) + "," + std::string(o.choices.back());
    case Kind::number_or_choice: return options::number_text(o.lo + 0.5 * (o.hi - o.lo));
    case Kind::frame_selection: return "0-3:2";
    case Kind::text:  // a poster is a PNG; an environment must be readable (the built-in one is)
      return o.id == "poster" ? "out.png" : o.id == "environment" ? "neutral" : "out.json";
    case Kind::existing_file: return "/dev/null";
    case Kind::flag: return "true";
    case Kind::size: return "64x48";
    case Kind::memory_size: return "512M";
    case Kind::up_direction: return "0,1,0.2";
  }
  return "";
}

// A value the row must refuse ("" if every text is valid).
std::string bad_value(const Option& o) {
  switch (o.kind) {
    case Kind::integer:
    case Kind::number: return options::number_text(o.hi + 1);
    case Kind::positive: return "0";
    case Kind::choice:
    case Kind::choice_list: return "no-such-choice";
    case Kind::number_or_choice: return options::number_text(o.hi + 1);
    case Kind::frame_selection: return "5-x";
    case Kind::flag: return "maybe";
    case Kind::size: return o.even_sides ? "65x48" : "8x48";
    case Kind::memory_size: return "12Q";
    case Kind::up_direction: return "sideways";
    case Kind::text:
    case Kind::existing_file: return "";
  }
  return "";
}

// Parses `args` with the registry's options of `command`; the values, or the CLI11 error text.
std::pair<options::Values, std::string> parse_cli(options::Command command, std::vector<std::string> args) {
  CLI::App app;
  options::Values values;
  options::add_registered_options(app, command, values);
  // The options the command requires (--out-dir, encode's -o), unless the test gives them.
  for (const Option& o : options::registry())
    if ((o.required & command) && std::find(args.begin(), args.end(), o.flag_in(command)) == args.end())
      args.insert(args.end(), {std::string(o.flag_in(command)), sample_value(o)});
  std::reverse(args.begin(), args.end());  // CLI11 parses a reversed vector
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    return {values, e.what()};
  }
  return {values, ""};
}

// JSON for a scene file holding `text` at the row's scene key.
nlohmann::json scene_with(const Option& o, const std::string& text) {
  nlohmann::json doc = {{"format", "meshtour-scene/1"}, {"model", {{"procedural", "sculpture"}}}};
  nlohmann::json value;
  if (o.kind == Kind::choice_list) {
    value = nlohmann::json::array();
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');) value.push_back(item);
  } else if (o.kind == Kind::flag) {
    value = text == "true" ? nlohmann::json(true) : text == "false" ? nlohmann::json(false) : nlohmann::json(text);
  } else if (o.kind == Kind::integer || o.kind == Kind::number || o.kind == Kind::positive ||
             (o.kind == Kind::number_or_choice && !text.empty() && (std::isdigit(static_cast<unsigned char>(text[0])) || text[0] == '-'))) {
    try {
      value = std::stod(text);
      if (o.kind == Kind::integer) value = std::stoll(text);
    } catch (const std::exception&) {
      value = text;
    }
  } else {
    value = text;
  }
  const std::string key(o.scene_key);
  const auto dot = key.find('.');
  if (dot == std::string::npos) doc[key] = value;
  else doc[key.substr(0, dot)][key.substr(dot + 1)] = value;
  return doc;
}

// The parts of a Scene the registry's rows set, as text, for comparisons.
std::string scene_fingerprint(const Scene& s) {
  nlohmann::json j = {{"w", s.render.width}, {"h", s.render.height}, {"fps", s.fps}, {"frames", s.frames},
                      {"up", s.up_auto ? std::string("auto") : s.up.name()}, {"path", std::string(path_mode_name(s.path_mode))}, {"fov", s.vertical_fov_deg}, {"auto", s.auto_fov},
                      {"elev", s.elevation_deg}, {"first", std::string(orbit_start_name(s.orbit_start))}, {"preset", s.render.shading.preset}, {"spp", s.render.samples_per_pixel},
                      {"bg", int(s.render.shading.background)}, {"exp", s.render.shading.exposure}, {"crease", s.render.shading.material.crease_angle_deg},
                      {"materials", s.render.shading.material.use_file_material},
                      {"denoise", s.render.denoise}, {"tone", int(s.render.shading.tone_mapping)},
                      {"env", s.render.shading.environment ? s.render.shading.environment->source : ""},
                      {"env_turn", s.render.shading.environment_rotation_deg}, {"env_scale", s.render.shading.environment_intensity},
                      {"env_shown", s.render.shading.environment_background}, {"bounces", s.render.shading.bounces},
                      {"layers", {s.render.layers.albedo, s.render.layers.normal, s.render.layers.depth}}, {"crf", s.crf},
                      {"file", s.path_file ? s.path_file->string() : ""}, {"grey", s.missing_textures_grey},
                      {"quality", s.quality}};
  const PaperPathOptions& p = s.path_search;
  const SurfaceOptions& f = p.surface;
  j["search"] = {f.tolerance, int(f.tolerance_unit), int(f.smoothing), f.smoothing_strength, int(f.curvature_fit), f.kappa_min,
                 int(f.face_samples), int(f.patch_measure), f.patch_normal_angle_deg, f.patches_on_unsmoothed, int(f.seed_order),
                 int(f.leftovers), f.keep_inaccurate_patches, int(f.weight_neighbourhood), f.merge_duplicate_vertices,
                 int(p.axis_point), p.rows, p.columns, int(p.cell_averaging), int(p.empty_columns), p.degree, p.gaze_scale,
                 p.position_scale, int(p.height_reference), int(p.gaze_radius)};
  return j.dump();
}

TEST(OptionRegistry, RowsAreWellFormedAndFlagsUniquePerCommand) {
  std::set<std::string_view> ids;
  for (const Option& o : options::registry()) {
    EXPECT_TRUE(ids.insert(o.id).second) << "two rows named " << o.id;
    EXPECT_TRUE(o.flag.starts_with("--")) << o.id;
    EXPECT_FALSE(o.help.empty()) << o.id;
    EXPECT_NE(o.commands, 0u) << o.id << " is taken by no command";
    if (!o.default_text.empty() && o.kind != Kind::frame_selection) {
      EXPECT_EQ(options::check_value(o, std::string(o.default_text)), "") << o.id << "'s default is outside its own range";
    }
    EXPECT_EQ(options::check_value(o, sample_value(o)), "") << o.id;
    if (const std::string bad = bad_value(o); !bad.empty()) {
      EXPECT_NE(options::check_value(o, bad), "") << o.id << " accepts " << bad;
    }
  }
  for (const auto command : kCommands) {
    std::set<std::string_view> flags;
    for (const Option& o : options::registry())
      if (o.commands & command) {
        EXPECT_TRUE(flags.insert(o.flag_in(command)).second) << o.flag_in(command) << " twice in " << command_name(command);
      }
  }
}

// CLI -> farm arguments -> CLI gives the same values; every command that takes a row accepts its
// sample value and refuses its bad one with the same check.
TEST(OptionRegistry, CommandLineAndFarmArgumentsRoundTrip) {
  for (const Option& o : options::registry()) {
    for (const auto command : kCommands) {
      if (!(o.commands & command)) continue;
      std::vector<std::string> args = {std::string(o.flag_in(command))};
      if (o.kind != Kind::flag) args.push_back(sample_value(o));
      const auto [values, error] = parse_cli(command, args);
      ASSERT_EQ(error, "") << o.id << " in " << command_name(command);
      ASSERT_EQ(values.count(std::string(o.id)), 1u) << o.id;
      EXPECT_EQ(values.at(std::string(o.id)), options::normalize_value(o, sample_value(o))) << o.id;
      if (const std::string bad = bad_value(o); !bad.empty() && o.kind != Kind::flag) {
        EXPECT_NE(parse_cli(command, {std::string(o.flag_in(command)), bad}).second, "") << o.id << " accepts " << bad;
      }
    }
    // What a farm passes on, the receiving command reads back as the same value.
    const std::pair<options::FarmPass, options::Command> passes[] = {
        {options::render_tasks, options::render}, {options::batch_tasks, options::batch}, {options::encode_job, options::encode}};
    for (const auto& [pass, receiver] : passes) {
      if (!(o.farm & pass)) continue;
      ASSERT_TRUE(o.commands & options::farm) << o.id << " is passed on by the farm, which does not take it";
      ASSERT_TRUE(o.commands & receiver) << o.id << " is passed to a command that does not take it";
      const options::Values given = {{std::string(o.id), options::normalize_value(o, sample_value(o))}};
      const auto [back, error] = parse_cli(receiver, options::forwarded_args(given, pass, receiver));
      EXPECT_EQ(error, "") << o.id;
      EXPECT_EQ(back.at(std::string(o.id)), given.at(std::string(o.id))) << o.id << " via " << command_name(receiver);
    }
  }
}

// Every option that changes the path or the pixels of a tour reaches the farm's render tasks.
TEST(OptionRegistry, FarmPassesEverySceneAndPathSettingToItsTasks) {
  for (const Option& o : options::registry()) {
    const options::Target target = options::target(o);
    if ((target != options::Target::scene && target != options::Target::path_search) || !(o.commands & options::farm)) continue;
    if (o.id == "crf" || o.id == "path-file") continue;  // the encode job's; the farm's own absolute path
    EXPECT_TRUE(o.farm & options::render_tasks) << o.id;
    EXPECT_TRUE(o.farm & options::batch_tasks) << o.id;
  }
}

// A scene file and the command line set the same scene; out-of-range values are refused by both.
TEST(OptionRegistry, SceneFileKeysMeanWhatTheFlagsMean) {
  const std::string minimal = R"({"format": "meshtour-scene/1", "model": {"procedural": "sculpture"}})";
  Scene untouched = parse_scene(minimal, "t.json", "/");
  apply_options(untouched, {});
  for (const Option& o : options::registry()) {
    if (o.scene_key.empty()) continue;
    const std::string text = options::normalize_value(o, sample_value(o));
    Scene by_file = parse_scene(scene_with(o, text).dump(), "t.json", "/");
    apply_options(by_file, {});
    Scene by_flag = parse_scene(minimal, "t.json", "/");
    apply_options(by_flag, {{std::string(o.id), text}});
    EXPECT_EQ(scene_fingerprint(by_file), scene_fingerprint(by_flag)) << o.id << ": the flag and the scene key disagree";
    EXPECT_NE(scene_fingerprint(by_flag), scene_fingerprint(untouched)) << o.id << " changed nothing";
    if (const std::string bad = bad_value(o); !bad.empty()) {
      EXPECT_THROW(parse_scene(scene_with(o, bad).dump(), "t.json", "/"), InputError) << o.id << " accepts " << bad;
    }
  }
}

// Every manifest column reads like its flag; a bad value makes only its item bad.
TEST(OptionRegistry, ManifestColumnsMeanWhatTheFlagsMean) {
  const auto dir = test::scratch_dir();
  for (const Option& o : options::registry()) {
    if (!o.manifest_column) continue;
    const std::string text = sample_value(o);
    const std::string column = o.id == "frame-count" ? "frames" : std::string(o.id);
    std::ofstream(dir / "m.csv") << "mesh," << column << "\na.ply,\"" << text << "\"\nb.ply,\"" << bad_value(o) << "\"\n";
    const auto items = read_batch_manifest(dir / "m.csv");
    ASSERT_EQ(items.size(), 2u);
    EXPECT_EQ(items[0].error, "") << o.id;
    EXPECT_EQ(items[0].values.at(std::string(o.id)), options::normalize_value(o, text)) << o.id;
    if (!bad_value(o).empty()) {
      EXPECT_NE(items[1].error, "") << o.id << " accepts " << bad_value(o);
    }
  }
}

// CRF's range is the codec's, wherever it is given.
TEST(OptionRegistry, CrfRangeIsTheCodecs) {
  const Option& crf = options::option("crf");
  EXPECT_EQ(options::check_value_for_codec(crf, "51", "h264"), "");
  EXPECT_NE(options::check_value_for_codec(crf, "52", "h264"), "");
  EXPECT_EQ(options::check_value_for_codec(crf, "63", "vp9"), "");
  EXPECT_NE(options::check_value_for_codec(crf, "18", "prores"), "");
  EXPECT_THROW(parse_scene(R"({"format": "meshtour-scene/1", "model": {"procedural": "sculpture"}, "output": {"crf": 60}})", "t", "/"),
               InputError);
  const auto dir = test::scratch_dir();
  std::ofstream(dir / "m.csv") << "mesh,crf\na.ply,60\nb.ply,30\n";
  const auto items = read_batch_manifest(dir / "m.csv");
  EXPECT_NE(items[0].error, "");
  EXPECT_EQ(items[1].error, "");
}

TEST(OptionRegistry, FovHelpNamesTheLensTheFeatureOrbitPlansFor) {
  // The number lives in FeatureOrbitOptions; the registry (which does not depend on pathgen)
  // repeats it in words, so a change of the lens must change the help too.
  const std::string lens = std::to_string(static_cast<int>(FeatureOrbitOptions{}.vertical_fov_deg)) + "-degree lens";
  EXPECT_NE(options::option("fov").help.find(lens), std::string::npos) << "--fov help does not name the " << lens;
}

// A command's own rows show a default that the bound field of its settings starts with: the row's
// text is what --help and docs/OPTIONS.md say, the field's initializer what the job does.
TEST(OptionRegistry, DefaultsShownAreTheSettingsDefaults) {
  const auto shown = [](std::string_view id) { return std::string(options::option(id).default_text); };
  const EvaluationOptions evaluation;
  EXPECT_EQ(shown("path-samples"), options::number_text(PaperPathOptions{}.samples));
  EXPECT_EQ(shown("coverage-samples"), options::number_text(static_cast<double>(evaluation.coverage.samples)));
  const char* const angles[] = {"seen-angle", "strict-angle", "stricter-angle", "strictest-angle"};
  for (std::size_t i = 0; i < std::size(angles); ++i)
    EXPECT_EQ(shown(angles[i]), options::number_text(evaluation.coverage.seen_angle_deg[i])) << angles[i];
  EXPECT_EQ(shown("feature-quantile"), options::number_text(evaluation.coverage.feature_quantile));
  EXPECT_EQ(shown("region-share"), options::number_text(evaluation.region_seen_share));
  // The tour's settings: the built-in scene's values.
  const Scene scene = default_scene();
  EXPECT_EQ(shown("width"), options::number_text(scene.render.width));
  EXPECT_EQ(shown("height"), options::number_text(scene.render.height));
  EXPECT_EQ(shown("fps"), options::number_text(scene.fps));
  EXPECT_EQ(shown("frame-count"), options::number_text(scene.frames));
  EXPECT_EQ(shown("spp"), options::number_text(scene.render.samples_per_pixel));
  EXPECT_EQ(shown("elevation"), options::number_text(scene.elevation_deg));
  EXPECT_EQ(shown("elevation"), options::number_text(Scene{}.elevation_deg)) << "a scene file without camera.elevation";
  EXPECT_EQ(shown("path"), std::string(path_mode_name(scene.path_mode)));
  EXPECT_EQ(shown("rows"), options::number_text(scene.path_search.rows));
  EXPECT_EQ(shown("columns"), options::number_text(scene.path_search.columns));
  EXPECT_EQ(shown("degree"), options::number_text(scene.path_search.degree));
}

TEST(OptionRegistry, ManifestAcceptsEveryPathMode) {
  const auto dir = test::scratch_dir();
  std::ofstream(dir / "m.csv") << "mesh,path\na.ply,feature-orbit\nb.ply,paper\nc.ply,turntable\n";
  for (const auto& item : read_batch_manifest(dir / "m.csv")) EXPECT_EQ(item.error, "") << item.index;
}

}  // namespace
}  // namespace meshtour

namespace meshtour {
namespace {

// --size: each name sets both sides (even, for every codec); a bad name is refused with the list
// of names; it cannot be given with --width or --height, and a manifest's width column replaces a
// batch-wide --size.
TEST(OptionRegistry, NamedSizesSetBothSidesAndExcludeWidthAndHeight) {
  for (const NamedSize& n : kNamedSizes) {
    const Scene s = resolve_scene("", {{"size", std::string(n.name)}});
    EXPECT_EQ(s.render.width, n.width) << n.name;
    EXPECT_EQ(s.render.height, n.height) << n.name;
    EXPECT_EQ(n.width % 2 + n.height % 2, 0) << n.name;
  }
  const auto size_of = [](const std::string& name) {
    const Scene s = resolve_scene("", {{"size", options::normalize_value(options::option("size"), name)}});
    return std::to_string(s.render.width) + "x" + std::to_string(s.render.height);
  };
  EXPECT_EQ(size_of("vertical"), "1080x1920");
  EXPECT_EQ(size_of("square"), "1080x1080");
  EXPECT_EQ(size_of("4K"), "3840x2160");
  EXPECT_EQ(size_of("1080p"), "1920x1080");

  // The names are no value of the options a size could be confused with.
  for (const NamedSize& n : kNamedSizes)
    for (const char* other : {"format", "preset", "codec", "background"})
      for (const std::string_view choice : options::option(other).choices) EXPECT_NE(choice, n.name) << other;

  const std::string bad = options::check_value(options::option("size"), "tall");
  for (const char* name : {"720p", "1080p", "4k", "vertical", "square"})
    EXPECT_NE(bad.find(name), std::string::npos) << bad;
  const auto [values, error] = parse_cli(options::tour, {"--size", "bogus"});
  EXPECT_NE(error.find("vertical"), std::string::npos) << error;

  for (const char* side : {"--width", "--height"}) {
    const std::string both = parse_cli(options::tour, {"--size", "square", side, "640"}).second;
    EXPECT_NE(both.find("excludes"), std::string::npos) << both;
  }
  const std::string from_scene_file = R"({"format": "meshtour-scene/1", "model": {"procedural": "sculpture"},
                                         "output": {"size": "vertical"}})";
  const Scene file = parse_scene(from_scene_file, "t.json", "/");
  EXPECT_EQ(file.render.width, 1080);
  EXPECT_EQ(file.render.height, 1920);
}

}  // namespace
}  // namespace meshtour
