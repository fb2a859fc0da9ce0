#include "options/option_registry.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "core/frame_sizes.h"
#include "core/memory_size.h"
#include "encoder/video_codecs.h"
#include "jobs/frame_range.h"
#include "mesh/up_axis.h"
#include "pathgen/cylinder.h"
#include "tracer/tracer.h"

// Each row names only the fields it sets (designated initializers); the others keep the defaults
// of their declarations, which is what GCC's -Wmissing-field-initializers would complain about.
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

namespace meshtour::options {
namespace {

constexpr unsigned kRendering = tour | render | batch | farm;  // commands that render a tour
constexpr unsigned kToTasks = render_tasks | batch_tasks;

const std::string_view kPatches = "Toroidal patches (docs/METHOD.md §3-§8)";
const std::string_view kGrid = "Cylinder and grid (§9-§11)";
const std::string_view kCurve = "Curve and camera (§12-§13)";

// The table. Order matters only where one value is applied on top of another (seconds after
// fps; look values after the preset).
std::vector<Option> make_registry() {
  std::vector<Option> r;
  const auto add = [&r](Option o) { r.push_back(std::move(o)); };
  // ---- Tour: size, timing, camera
  // Before width and height: a scene file's output.width or output.height refines its output.size.
  static const std::string size_help = [] {
    std::string help = "Frame size by name, instead of --width and --height:";
    for (const NamedSize& s : kNamedSizes)
      help += std::string(&s == &kNamedSizes.front() ? " " : ",\n") + std::string(s.name) + " " + std::to_string(s.width) +
              "x" + std::to_string(s.height) + " (" + std::string(s.use) + ")";
    return help;
  }();
  std::vector<std::string_view> size_names;
  for (const NamedSize& s : kNamedSizes) size_names.push_back(s.name);
  add({.id = "size", .flag = "--size", .kind = Kind::choice, .type_name = "NAME", .choices = size_names, .ignore_case = true,
       .help = size_help, .scene_key = "output.size", .manifest_column = true, .commands = kRendering | path | evaluate,
       .farm = kToTasks, .excludes = "width,height"});
  add({.id = "width", .flag = "--width", .kind = Kind::integer, .lo = 2, .hi = 16384, .default_text = "1280",
       .help = "Frame width in pixels, even (default 1280)", .scene_key = "output.width", .manifest_column = true,
       .commands = kRendering | path | evaluate, .farm = kToTasks, .excludes = "size"});
  add({.id = "height", .flag = "--height", .kind = Kind::integer, .lo = 2, .hi = 16384, .default_text = "720",
       .help = "Frame height in pixels, even (default 720)", .scene_key = "output.height", .manifest_column = true,
       .commands = kRendering | path | evaluate, .farm = kToTasks, .excludes = "size"});
  add({.id = "fps", .flag = "--fps", .kind = Kind::integer, .lo = 1, .hi = 240, .default_text = "30",
       .help = "Frames per second (default 30; encode: the manifest's, else 30)", .scene_key = "timing.fps",
       .manifest_column = true, .commands = kRendering | path | encode, .farm = kToTasks | encode_job});
  add({.id = "frame-count", .flag = "--frames", .kind = Kind::integer, .lo = 1, .hi = 1000000, .default_text = "120",
       .help = "Frames in one loop of the path (default 120)",
       .long_help = "The tour's length. `render` spells it --frame-count, because its --frames selects frames.",
       .scene_key = "timing.frames", .manifest_column = true, .commands = kRendering | path | evaluate,
       .farm = kToTasks, .alt_flag = "--frame-count", .alt_flag_commands = render, .excludes = "seconds"});
  add({.id = "seconds", .flag = "--seconds", .kind = Kind::number, .lo = 0.001, .hi = 100000,
       .help = "Length of the video in seconds (sets the frame count = seconds x fps)", .manifest_column = true,
       .commands = kRendering, .farm = kToTasks, .excludes = "frame-count"});
  add({.id = "up", .flag = "--up", .kind = Kind::choice, .choices = {"x", "y", "z", "-x", "-y", "-z", "+x", "+y", "+z", "auto"},
       .ignore_case = true, .default_text = "auto",
       .help = "The model's up axis: x, y, z, -x, -y, -z or auto (the side the model stands on: its firmest rest and\n"
               "flattest base, never across its plane of symmetry; y when no side clearly wins, and y for glTF unless\n"
               "the shape clearly disagrees; said on stderr) (default auto for mesh files, y for the built-in model;\n"
               "a Voyager scene's model is +y, stood up by its document)",
       .scene_key = "up", .manifest_column = true, .commands = kRendering | path | evaluate, .farm = kToTasks,
       .meanings = {{.commands = path,
                     .help = "Up direction of the model = axis of the bounding cylinder the camera circles (I-18): "
                             "x, y, z, -x, -y, -z, a vector such as 0,1,0.2, 'longest-aabb' (longest side of the "
                             "bounding box), 'pca' (principal axis of the surface) or 'auto' (the side the model rests on most "
                             "firmly, else y)",
                     .kind = Kind::up_direction}}});
  add({.id = "quality", .flag = "--quality", .kind = Kind::choice, .choices = {"thumb", "low", "medium", "high", "highest", "ar"},
       .ignore_case = true,
       .help = "A Voyager scene's (.svx.json) Web3D derivative to tour, by its quality (default: the highest whose model\n"
               "file is on disk, Highest to Thumb; AR only when named)",
       .long_help = "Only for Voyager documents (docs/FORMATS.md#voyager-scenes): their models list derivatives of "
                    "several qualities, each a file of its own. A quality the document lists but whose file is not "
                    "on disk is an error naming the file.",
       .scene_key = "quality", .manifest_column = true, .commands = kRendering | path | evaluate, .farm = kToTasks});
  add({.id = "missing-textures", .flag = "--missing-textures", .kind = Kind::choice, .choices = {"error", "grey"},
       .default_text = "error",
       .help = "A texture the model names that is missing or unreadable: error (default; the message names the file and\n"
               "the material) or grey (its faces are rendered untextured, in the look's colour, with a warning)",
       .scene_key = "missing_textures", .manifest_column = true, .commands = kRendering, .farm = kToTasks});
  add({.id = "json", .flag = "--json", .kind = Kind::flag,
       .help = "Print the report as one JSON object on stdout instead of text", .commands = info});
  add({.id = "path", .flag = "--path", .kind = Kind::choice, .choices = {"feature-orbit", "paper", "turntable"},
       .default_text = "feature-orbit",
       .help = "Camera path: feature-orbit (default; an orbit whose elevation and distance are chosen to show the most\n"
               "feature area smoothly; see 'meshtour evaluate --compare' for how it compares on your meshes),\n"
               "paper (the toroidal-patch method of Choi et al. 2024, see 'meshtour path --help') or turntable\n"
               "(circular orbit around the up axis)",
       .scene_key = "camera.path", .manifest_column = true, .commands = kRendering | path | evaluate, .farm = kToTasks,
       .meanings = {{.commands = path,
                     .help = "Path mode: paper (this method; --plot and --debug-dir describe it), turntable or "
                             "feature-orbit (see 'meshtour evaluate --help'; -o writes their path file too); the other modes "
                             "need a coordinate --up axis",
                     .default_text = "paper"}}});
  add({.id = "path-file", .flag = "--path-file", .kind = Kind::existing_file,
       .help = "Use the camera path in this file, written by 'meshtour path -o' for any mode (overrides --path; no path\n"
               "search). Refused if the file was made for other settings (aspect, --fov, --frames, --up, search options)",
       .long_help = "Not forwarded as given by `farm slurm`: the farm passes its tasks the file's absolute path.",
       .scene_key = "camera.path_file", .commands = kRendering | evaluate});
  add({.id = "fov", .flag = "--fov", .kind = Kind::number_or_choice, .lo = 5, .hi = 120, .choices = {"auto"},
       .default_text = "auto",
       .help = "Vertical field of view: degrees (5-120), or auto (default): the paper path keeps its camera distance\n"
               "and the fov is fitted so every vertex stays in frame at every frame; the feature orbit plans its\n"
               "distances for a long 10-degree lens (about 135 mm: it sees the surface more squarely than a wide one);\n"
               "the turntable uses 35 degrees and fits its radius. A fixed fov moves the paper path's camera back\n"
               "where needed instead, and the feature orbit plans for it.",
       .scene_key = "camera.fov", .manifest_column = true, .commands = kRendering | path | evaluate, .farm = kToTasks});
  add({.id = "elevation", .flag = "--elevation", .kind = Kind::number, .lo = -80, .hi = 80, .default_text = "18",
       .help = "Turntable: camera elevation above the model's centre, degrees (default 18)",
       .scene_key = "camera.elevation", .manifest_column = true, .commands = kRendering | path | evaluate, .farm = kToTasks});
  add({.id = "first-view", .flag = "--first-view", .kind = Kind::choice, .choices = {"preferred", "best-covering"},
       .default_text = "best-covering",
       .help = "Feature orbit: the view its loop starts at (frame 0, the poster): best-covering (default; the view that\n"
               "sees the most feature area) or preferred (the view a published model of viewpoint preference, Gao et al.\n"
               "2016, scores highest; nearer people's choice on fewer labelled scans: docs/EVALUATION.md)",
       .scene_key = "camera.first_view", .manifest_column = true, .commands = kRendering | path | evaluate, .farm = kToTasks});
  // ---- Look and samples
  add({.id = "preset", .flag = "--preset", .kind = Kind::choice, .choices = {"studio", "plain"},
       .help = "Look: studio (key, fill and rim lights, soft shadows, ambient occlusion, shadow-catching ground, "
               "gradient) or plain (even light, no shadows, for catalogues); the scene file's own look values still apply "
               "(default: the scene's, else studio)",
       .scene_key = "look.preset", .manifest_column = true, .commands = kRendering, .farm = kToTasks});
  add({.id = "environment", .flag = "--environment", .kind = Kind::text, .type_name = "FILE", .default_text = "none",
       .help = "Image-based light in place of the look's uniform sky: an equirectangular HDR or EXR image (2:1), or\n"
               "neutral (a built-in studio: softbox above, strips at the sides, a grey room). Its light lights the\n"
               "model along the occlusion rays (importance-sampled by the image's luminance: a sun casts its own\n"
               "shadow, on the model and the ground) and in the reflections of glTF materials; the look's lights\n"
               "stay; the background stays the look's (--environment-background shown shows it)",
       .scene_key = "look.environment", .manifest_column = true, .commands = kRendering, .farm = kToTasks});
  add({.id = "environment-rotation", .flag = "--environment-rotation", .kind = Kind::number, .lo = -360, .hi = 360,
       .default_text = "0", .help = "Turns the environment about the up axis (degrees)", .scene_key = "look.environment_rotation",
       .manifest_column = true, .commands = kRendering, .farm = kToTasks});
  add({.id = "environment-intensity", .flag = "--environment-intensity", .kind = Kind::number, .lo = 0, .hi = 1000,
       .default_text = "1", .help = "Multiplies the environment's light (neutral: 1 lights a white surface facing up as 1.0)",
       .scene_key = "look.environment_intensity", .manifest_column = true, .commands = kRendering, .farm = kToTasks});
  add({.id = "environment-background", .flag = "--environment-background", .kind = Kind::choice, .choices = {"hidden", "shown"},
       .ignore_case = true, .default_text = "hidden",
       .help = "With --environment: shown puts the environment behind the model (and under the ground's\n"
               "shadows) in place of the look's gradient; hidden (default) keeps the gradient. Transparent\n"
               "frames stay transparent",
       .scene_key = "look.environment_background", .manifest_column = true, .commands = kRendering, .farm = kToTasks});
  add({.id = "bounces", .flag = "--bounces", .kind = Kind::integer, .lo = 0, .hi = 4, .default_text = "0",
       .help = "Diffuse interreflections (0-4, default 0): where a sample's occlusion ray meets the model, the light\n"
               "that point reflects (the lights through a shadow ray, the sky or --environment through an occlusion\n"
               "ray of its own, and so on up to N surfaces deep) in place of darkness: crevices and the insides of\n"
               "shells brighten and take the colour of their walls. Each bounce adds up to two rays per sample\n"
               "where it applies. No effect without occlusion rays (the plain look); the floor reflects nothing\n"
               "(it only catches shadows). docs/RENDERING.md says how many a look needs",
       .scene_key = "look.bounces", .manifest_column = true, .commands = kRendering, .farm = kToTasks});
  add({.id = "materials", .flag = "--materials", .kind = Kind::choice, .choices = {"file", "look"}, .ignore_case = true,
       .default_text = "file",
       .help = "Whose shading a surface gets: file (default: a glTF material's own metallic-roughness BRDF, emission\n"
               "and unlit flag, as the glTF specification's Appendix B says; an OBJ material's roughness from its\n"
               "MTL's Pr or Ns/Ks, its Ke and opacity, docs/FORMATS.md) or look (the look's diffuse base and\n"
               "highlight everywhere, on the file's colours and maps: the studio look of a clay scan)",
       .scene_key = "look.materials", .manifest_column = true, .commands = kRendering, .farm = kToTasks});
  add({.id = "crease-angle", .flag = "--crease-angle", .kind = Kind::number, .lo = 0, .hi = 180, .default_text = "60",
       .help = "Edges where faces meet at more than this angle (degrees) are shaded sharp, smaller ones smooth\n"
               "(default 60: a box, a plinth or a CAD part keeps flat faces, a scan stays smooth; 180 smooths every edge)",
       .scene_key = "look.crease_angle", .manifest_column = true, .commands = kRendering, .farm = kToTasks});
  add({.id = "spp", .flag = "--spp", .kind = Kind::integer, .lo = 1, .hi = 4096, .default_text = "16",
       .help = "Samples per pixel: Owen-scrambled Sobol points in Z order (neighbouring pixels' samples fill each\n"
               "other's gaps). The raw frame's error falls faster than 1/sqrt(spp) (bunny at 1280x720: 2.4x from 4\n"
               "to 16, 2.3x from 16 to 64); denoised, 16 is closer to the converged frame than raw 128 (relative\n"
               "error: bunny 0.49 against 0.66 %, default scene 0.26 against 0.36 %). Powers of two work best\n"
               "(default 16)",
       .scene_key = "output.spp", .manifest_column = true, .commands = kRendering, .farm = kToTasks});
  add({.id = "denoise", .flag = "--denoise", .kind = Kind::choice, .choices = {"on", "off"}, .ignore_case = true,
       .default_text = "on",
       .help = "Denoise the frames (default on): PNG frames and the video show the denoised frame; EXR frames keep\n"
               "the raw frame as the main layer and add the denoised one as the layer 'denoised' (encode uses it)",
       .long_help = "Filters the lighting, not the colours (tracer/denoiser.h): the frame is divided by its unshadowed "
                    "light, splatted with the same sample weights, so textures, vertex colours and silhouettes stay "
                    "sharp; the visibility left is fitted over a disc of radius 5 by weighted least squares on the "
                    "pixel offset and the tilt of the surface normal (so small bumps keep their occlusion), weighted "
                    "by normal, depth and a two-pass a-trous guide of its luminance, and multiplied back. "
                    "Deterministic: the same bits for any thread count, CPU and farm split.",
       .scene_key = "output.denoise", .manifest_column = true, .commands = kRendering, .farm = kToTasks});
  add({.id = "background", .flag = "--background", .kind = Kind::choice, .choices = {"gradient", "transparent"},
       .help = "gradient, or transparent (PNG frames get straight alpha: clear background and ground, the ground's\n"
               "shadows stay as partial alpha; --alpha keeps it in .mov and .webm video)",
       .scene_key = "look.background", .manifest_column = true, .commands = kRendering, .farm = kToTasks});
  add({.id = "exposure", .flag = "--exposure", .kind = Kind::number, .lo = -20, .hi = 20,
       .help = "Exposure in stops for PNG frames and the video (EXR stays linear; encode: for EXR frames, default from\n"
               "the EXR header)",
       .scene_key = "look.exposure", .manifest_column = true, .commands = kRendering | encode, .farm = kToTasks});
  add({.id = "exr-layers", .flag = "--exr-layers", .kind = Kind::choice_list, .choices = {"albedo", "normal", "depth"},
       .help = "Extra layers in EXR frames: albedo, normal, depth (alpha is always there)", .scene_key = "output.exr_layers",
       .commands = kRendering, .farm = kToTasks});
  // ---- Video
  add({.id = "crf", .flag = "--crf", .kind = Kind::integer, .lo = 0, .hi = 63,
       .help = "Video quality (CRF), lower is better; the range and default are the codec's. h264: 18 looks lossless,\n"
               "23 is x264's default, 0 is lossless but High 4:4:4, which browsers do not play; prores, ffv1 and gif take none",
       .scene_key = "output.crf", .manifest_column = true, .commands = tour | batch | farm | encode,
       .farm = encode_job | batch_tasks, .codec_dependent = true});
  add({.id = "codec", .flag = "--codec", .kind = Kind::choice, .choices = {"h264", "prores", "ffv1", "vp9", "gif"},
       .default_text = "h264", .help = "Video codec: h264 (default, .mp4), prores (.mov), ffv1 (.mkv), vp9 (.webm) or gif",
       .commands = farm | encode, .farm = encode_job});
  add({.id = "alpha", .flag = "--alpha", .kind = Kind::flag,
       .help = "Keep the frames' alpha in the video, straight (not premultiplied) as editors and browsers expect:\n"
               "ProRes 4444 (.mov), VP9 with alpha (.webm) or FFV1 RGBA (.mkv); h264 and gif cannot carry it.\n"
               "Needs transparent frames (--background transparent; encode: RGBA PNG frames). Without it they\n"
               "are shown over black. farm slurm: its encode job keeps it (give --codec prores, vp9 or ffv1)",
       .commands = tour | farm | encode, .farm = encode_job});
  // ---- Frames and jobs
  add({.id = "frame-selection", .flag = "--frames", .kind = Kind::frame_selection, .default_text = "all",
       .help = "Frames to use, numbered from 0: all (default), A, A-B, A-B:S (every S-th), or a comma-separated\n"
               "list of these, e.g. 0-9,20,30-40:2; clamped to the tour's frame count",
       .commands = render | encode});
  add({.id = "format", .flag = "--format", .kind = Kind::choice, .choices = {"png", "exr", "png+exr"}, .default_text = "png",
       .help = "Frame image format: png (8-bit sRGB; what encode reads by default), exr (half float, linear) or png+exr",
       .commands = tour | render | farm});
  add({.id = "threads", .flag = "--threads", .kind = Kind::integer, .lo = 0, .hi = 1000000, .default_text = "0",
       .help = "Worker threads; 0 (default) = SLURM_CPUS_PER_TASK when set, else all cores; more than the cores are capped.\n"
               "Results do not depend on it",
       .commands = tour | render | batch | path | evaluate});
  add({.id = "gltf", .flag = "--gltf", .kind = Kind::text,
       .help = "Also write the camera path as glTF 2.0 (FILE.gltf + FILE.bin: an animated camera with the tour's field of view)",
       .commands = tour | path});
  add({.id = "camera-frames", .flag = "--camera-frames", .kind = Kind::text,
       .help = "Also write every frame's eye, target, up and field of view (.csv or .json)", .commands = tour | path});
  // ---- Catalogue deliverables: poster still, caption and title card (burned into the video only; the
  // frames `render` writes stay clean, so `encode` can caption one set of frames in several languages).
  constexpr unsigned kVideoMakers = tour | batch | farm | encode;
  add({.id = "poster", .flag = "--poster", .kind = Kind::text,
       .type_name = "PNG",
       .help = "Also write the poster still (PNG): the tour's first frame, its preferred view, bit-identical to that frame\n"
               "when the sizes agree (batch: default <video name>.poster.png beside the video; encode: from the frames directory)",
       .long_help = "The feature orbit (the default path) starts at the view a published model of viewpoint preference "
                    "scores highest (docs/EVALUATION.md); the turntable starts at its front, the paper's path at its start. "
                    "In a batch manifest the column is a plain file name inside --out-dir.",
       .manifest_column = true, .commands = tour | farm | encode, .farm = encode_job});
  add({.id = "poster-size", .flag = "--poster-size", .kind = Kind::size, .lo = 16, .hi = 16384,
       .help = "Poster size WIDTHxHEIGHT (default: the frames' size); the first frame is cropped to its aspect and resampled",
       .manifest_column = true, .commands = kVideoMakers, .farm = encode_job | batch_tasks, .even_sides = true});
  add({.id = "caption", .flag = "--caption", .kind = Kind::text,
       .help = "Text burned into the video (UTF-8, e.g. \"Nefertiti \u2014 ÄM 21300\"); the frames stay clean. Text wider\n"
               "than the frame is an error naming the limit, never cut",
       .manifest_column = true, .commands = kVideoMakers, .farm = encode_job | batch_tasks});
  add({.id = "caption-position", .flag = "--caption-position", .kind = Kind::choice,
       .choices = {"bottom-left", "bottom", "bottom-right", "top-left", "top", "top-right"}, .ignore_case = true,
       .default_text = "bottom-left", .help = "Where the caption goes: bottom-left (default), bottom, bottom-right, top-left, top, top-right",
       .manifest_column = true, .commands = kVideoMakers, .farm = encode_job | batch_tasks});
  add({.id = "caption-size", .flag = "--caption-size", .kind = Kind::integer, .lo = 6, .hi = 1000,
       .help = "Caption font size in pixels (default: 1/18 of the frame height, at least 10)",
       .manifest_column = true, .commands = kVideoMakers, .farm = encode_job | batch_tasks});
  add({.id = "font", .flag = "--font", .kind = Kind::existing_file,
       .help = "Caption font file (TrueType/OpenType; default: DejaVu Sans, found through fontconfig)",
       .commands = kVideoMakers, .farm = encode_job | batch_tasks});
  add({.id = "title-card", .flag = "--title-card", .kind = Kind::number, .lo = 0.5, .hi = 60,
       .help = "Open the video on the poster frame with the caption large for SECONDS, then cross-fade into the tour",
       .manifest_column = true, .commands = kVideoMakers, .farm = encode_job | batch_tasks});
  add({.id = "web", .flag = "--web", .kind = Kind::flag,
       .help = "Web outputs: per item an H.264 MP4, a VP9 WebM and the poster, and index.html, a contact sheet of the batch",
       .commands = batch | farm, .farm = batch_tasks});
  add({.id = "page-only", .flag = "--page-only", .kind = Kind::flag,
       .help = "Write only the contact sheet (index.html) from the batch summaries already in --out-dir (the farm's last job)",
       .commands = batch});
  // ---- The commands' own settings: inputs and outputs, progress, resources, the farm, the path
  // command's extra outputs and the evaluation's yardstick.
  add({.id = "output", .flag = "--output", .kind = Kind::text, .short_flag = "-o", .type_name = "FILE",
       .help = "Video file to write (.mp4); default: <input name>.mp4 in the current directory",
       .commands = tour | farm | path | encode, .required = encode,
       .meanings = {{.commands = farm, .help = "Video file name inside --out-dir (default <input name> + the codec's extension)"},
                    {.commands = path,
                     .help = "Path file to write (JSON; docs/FORMATS.md), for any --path mode, with the settings it was made "
                             "for (what --path-file needs to render it). Default for the paper path: <mesh name>.path.json "
                             "in the current folder; the other modes write one only when -o is given"},
                    {.commands = encode, .help = "Video file to write; its extension must match the codec"}}});
  add({.id = "frames-dir", .flag = "--frames-dir", .kind = Kind::text, .type_name = "DIR",
       .help = "Also write every frame as an image into this directory (frame_000000.png, ...)", .commands = tour});
  add({.id = "out-dir", .flag = "--out-dir", .kind = Kind::text, .type_name = "DIR",
       .help = "Directory for the frames and the manifest (created if needed)", .commands = render | batch | farm,
       .required = render | batch | farm,
       .meanings = {{.commands = batch, .help = "Directory for the videos and batch-summary.json (created if needed)"},
                    {.commands = farm,
                     .help = "Directory for the scripts, the path, the frames, logs and the video (shared by all nodes)"}}});
  add({.id = "overwrite", .flag = "--overwrite", .kind = Kind::flag,
       .help = "Render the selected frames again even if they exist", .commands = render});
  add({.id = "manifest", .flag = "--manifest", .kind = Kind::existing_file,
       .help = "A batch manifest (CSV or JSON, see 'meshtour batch --help'): one array task per item", .commands = farm});
  add({.id = "item", .flag = "--item", .kind = Kind::integer, .lo = 0, .hi = 1000000000,
       .help = "Run only the item with this 0-based index (one farm array task per item)", .commands = batch});
  add({.id = "chunk-size", .flag = "--chunk-size", .kind = Kind::integer, .lo = 1, .hi = 1000000, .default_text = "10",
       .help = "Frames per array task (default 10)", .commands = farm});
  add({.id = "partition", .flag = "--partition", .kind = Kind::text, .type_name = "NAME",
       .help = "Slurm partition (sbatch --partition; default: the cluster's default)", .commands = farm});
  add({.id = "time", .flag = "--time", .kind = Kind::text, .type_name = "TIME",
       .help = "Time limit of each task (sbatch --time, e.g. 30 or 2:00:00)", .commands = farm});
  add({.id = "cpus-per-task", .flag = "--cpus-per-task", .kind = Kind::integer, .lo = 1, .hi = 1024, .default_text = "1",
       .help = "CPUs per task (sbatch --cpus-per-task); render uses that many threads (default 1)", .commands = farm});
  add({.id = "executable", .flag = "--executable", .kind = Kind::text,
       .help = "The meshtour executable the jobs run (default: this one)", .commands = farm});
  add({.id = "submit", .flag = "--submit", .kind = Kind::flag, .help = "Submit the jobs with sbatch and print their ids",
       .commands = farm});
  add({.id = "progress", .flag = "--progress", .kind = Kind::choice, .choices = {"auto", "bar", "json", "none"},
       .default_text = "auto",
       .help = "Progress on stderr: bar (frames done, frames/s, time left), json (one JSON line per finished frame\n"
               "and a summary line, for farm logs), none, or auto (default): bar on a terminal, json otherwise",
       .commands = tour | render | batch});
  add({.id = "max-memory", .flag = "--max-memory", .kind = Kind::memory_size, .type_name = "SIZE",
       .help = "Memory the job may use, e.g. 512M or 8G (default: 75% of this machine's memory). A job whose "
               "estimated peak is larger is refused before it allocates anything (in a batch: that item fails). "
               "`farm slurm` gives it to every task and asks Slurm for it (--mem)",
       .commands = tour | render | path | batch | farm, .farm = kToTasks, .group = "Resources"});
  add({.id = "verbose", .flag = "--verbose", .kind = Kind::flag,
       .help = "Report the time and memory (resident, peak) of every stage on stderr", .commands = tour | render | path,
       .group = "Resources"});
  add({.id = "quiet", .flag = "--quiet", .kind = Kind::flag, .short_flag = "-q", .help = "Print nothing but errors",
       .commands = tour | render | batch | farm | path | evaluate | encode,
       .meanings = {{.commands = batch, .help = "Print nothing but errors and the summary table"},
                    {.commands = farm, .help = "Print nothing but errors and the job ids"},
                    {.commands = path | evaluate, .help = "Print nothing on success"}}});
  add({.id = "plot", .flag = "--plot", .kind = Kind::text, .type_name = "PNG",
       .help = "Also draw a PNG of the grid weights over the (angle, height) domain with the control points (white discs), "
               "the base (white), gaze (cyan) and position (magenta) curves and the start cell (red)",
       .commands = path});
  add({.id = "debug-dir", .flag = "--debug-dir", .kind = Kind::text, .type_name = "DIR",
       .help = "Also write the debug outputs of §14 into this folder: patches.ply, face_weights.ply, cell_weights.ply (the "
               "smoothed mesh in model units, faces coloured by patch / by w(f) / by the weight of their cell, green = low, "
               "red = high) and samples.csv (the sampled curves and camera poses)",
       .commands = path});
  add({.id = "overview", .flag = "--overview", .kind = Kind::text, .type_name = "PNG",
       .help = "Also render a picture of the path (PNG): the model, its bounding cylinder (blue-grey), the camera positions "
               "(magenta), the points looked at (cyan), sight lines (yellow) and the start (red)",
       .commands = path});
  add({.id = "overview-size", .flag = "--overview-size", .kind = Kind::size, .lo = 16, .hi = 16384, .default_text = "1200x900",
       .help = "Size of the --overview picture, WIDTHxHEIGHT", .commands = path});
  add({.id = "path-samples", .flag = "--samples", .kind = Kind::integer, .lo = 1, .hi = 1000000, .default_text = "360",
       .help = "Samples per loop K in samples.csv (§13.3)", .commands = path});
  add({.id = "compare", .flag = "--compare", .kind = Kind::flag,
       .help = "Evaluate turntable, paper and feature-orbit and print one table", .commands = evaluate});
  add({.id = "json-file", .flag = "--json", .kind = Kind::text, .type_name = "FILE",
       .help = "Also write the numbers as JSON: {\"modes\": {\"<mode>\": {\"feature_coverage\": ..., "
               "\"surface_coverage\": ..., \"feature_min_frames\": ..., \"feature_median_frames\": ..., "
               "\"camera_max_angular_speed\": ..., \"view_max_angular_speed\": ..., "
               "\"view_max_angular_acceleration\": ..., \"frames_out_of_frame\": ..., \"min_edge_margin\": ..., "
               "\"frames_below_floor\": ..., \"objective\": ..., "
               "\"frame_scores\": [...], \"definitions\": {\"patch-density-75deg\": {\"feature_coverage\": ..., "
               "\"surface_coverage\": ..., \"feature_min_frames\": ..., \"feature_median_frames\": ...}, "
               "\"saliency-75deg\": {...}, \"patch-density-60deg\": {...}, \"saliency-60deg\": {...}, "
               "\"patch-density-45deg\": {...}, \"saliency-45deg\": {...}, \"patch-density-30deg\": {...}, "
               "\"saliency-30deg\": {...}}}}} "
               "(fractions, rad/frame, rad/frame^2; the top-level coverage keys are the first definition's)",
       .commands = evaluate});
  add({.id = "coverage-samples", .flag = "--samples", .kind = Kind::integer, .lo = 1024, .hi = 1 << 24, .default_text = "65536",
       .help = "Surface samples the coverage is measured on", .commands = evaluate});
  // One row per seen-well angle of CoverageOptions, in its order (each names a pair of definitions).
  add({.id = "seen-angle", .flag = "--seen-angle", .kind = Kind::number, .lo = 1, .hi = 90, .default_text = "75",
       .help = "A visible sample is seen well when its normal is within this many degrees of the direction to the camera",
       .commands = evaluate});
  add({.id = "strict-angle", .flag = "--strict-angle", .kind = Kind::number, .lo = 1, .hi = 90, .default_text = "60",
       .help = "The seen-well angle of the second pair of feature definitions (stricter)", .commands = evaluate});
  add({.id = "stricter-angle", .flag = "--stricter-angle", .kind = Kind::number, .lo = 1, .hi = 90, .default_text = "45",
       .help = "The seen-well angle of the third pair of feature definitions (stricter still)", .commands = evaluate});
  add({.id = "strictest-angle", .flag = "--strictest-angle", .kind = Kind::number, .lo = 1, .hi = 90, .default_text = "30",
       .help = "The seen-well angle of the fourth pair of feature definitions (the strictest)", .commands = evaluate});
  add({.id = "feature-quantile", .flag = "--feature-quantile", .kind = Kind::number, .lo = 0, .hi = 0.99, .default_text = "0.75",
       .help = "Features: the samples at or above this quantile of a measure", .commands = evaluate});
  add({.id = "region-share", .flag = "--region-share", .kind = Kind::number, .lo = 0.01, .hi = 1, .default_text = "0.25",
       .help = "Share of a feature region's area that must be seen well for the region to count as seen in a frame",
       .commands = evaluate});
  add({.id = "input-format", .flag = "--input-format", .kind = Kind::choice, .choices = {"png", "exr"},
       .help = "Frame files to read: png or exr (default: png when present)", .commands = encode});
  add({.id = "tone-mapping", .flag = "--tone-mapping", .kind = Kind::choice, .choices = tone_mapping_names(),
       .default_text = "filmic",
       .help = "Tone curve of PNG frames and the video: filmic (ACES fit: rolls highlights off, deepens shadows),\n"
               "clamp (none: over 1 clips) or pbr-neutral (Khronos PBR Neutral, as model-viewer and f3d: colours\n"
               "under 0.8 shown as they are, only highlights compressed). EXR frames stay linear and record it",
       .scene_key = "look.tone_mapping", .manifest_column = true, .commands = kRendering | encode, .farm = kToTasks,
       .meanings = {{.commands = encode, .help = "EXR frames: filmic, clamp or pbr-neutral (default: from the EXR header, else filmic)",
                     .default_text = "from the EXR header"}}});
  // ---- The toroidal-patch path (docs/METHOD.md); the feature orbit uses the patch options too.
  const unsigned kPathCommands = kRendering | path | evaluate;
  add({.id = "tolerance", .flag = "--tolerance", .kind = Kind::positive, .default_text = "0.001",
       .help = "Patch tolerance epsilon: largest distance between a face and the torus of its patch, "
               "in units of --tolerance-unit (default: half the bounding box's largest side). Smaller = more, smaller patches",
       .scene_key = "patches.tolerance", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks, .group = kPatches});
  add({.id = "tolerance-unit", .flag = "--tolerance-unit", .kind = Kind::choice,
       .choices = {"diagonal", "box-extent", "box-half-extent"}, .ignore_case = true, .default_text = "box-half-extent",
       .help = "The length --tolerance is a fraction of (I-34, docs/FIDELITY.md): half the bounding box's largest "
               "side (default: the model scaled into the cube [-1, 1]^3, which reproduces the paper's tables on the "
               "bunny and the horse), that side, or the bounding-box diagonal (the specification's text). The feature "
               "orbit's and evaluate's patch density on the coarse proxy keep the diagonal",
       .scene_key = "patches.tolerance_unit", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks,
       .group = kPatches});
  add({.id = "smoothing", .flag = "--smoothing", .kind = Kind::choice, .choices = {"implicit", "none", "taubin", "pmp-default"},
       .ignore_case = true, .default_text = "implicit",
       .help = "Smoothing before curvature estimation (I-2, I-3): implicit = one backward-Euler "
               "cotangent-Laplacian step with dt = strength * (mean edge length)^2; none; taubin "
               "(lambda|mu, 10 iterations); pmp-default (dt = 1e-3, strong)",
       .scene_key = "patches.smoothing", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks, .group = kPatches});
  add({.id = "smoothing-strength", .flag = "--smoothing-strength", .kind = Kind::positive, .default_text = "1",
       .help = "c_s of dt = c_s * (mean edge length)^2 for --smoothing implicit (I-2). 1 halves "
               "wiggles about 6 edges long; 0.25-0.5 keeps more detail",
       .scene_key = "patches.smoothing_strength", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks,
       .group = kPatches});
  add({.id = "curvature-fit", .flag = "--curvature-fit", .kind = Kind::choice, .choices = {"cubic", "quadratic"},
       .ignore_case = true, .default_text = "cubic",
       .help = "Principal-curvature fit over the 1-ring (I-4): cubic = Goldfeather-Interrante with "
               "positions and normals; quadratic = the 3 quadratic terms only",
       .scene_key = "patches.curvature_fit", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks, .group = kPatches});
  add({.id = "kappa-min", .flag = "--kappa-min", .kind = Kind::positive, .default_text = "1e-06",
       .help = "Smallest curvature magnitude used for a torus, per diagonal (I-9): flat and "
               "cylindrical points get radii up to 1/kappa-min",
       .scene_key = "patches.kappa_min", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks, .group = kPatches});
  add({.id = "face-samples", .flag = "--face-samples", .kind = Kind::choice, .choices = {"seven", "vertices", "edges-4"},
       .ignore_case = true, .default_text = "seven",
       .help = "Points of a face tested against a torus (I-11): seven = corners, edge midpoints "
               "and centroid; vertices = the 3 corners; edges-4 = seven plus the quarter points of every edge (I-32)",
       .scene_key = "patches.face_samples", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks, .group = kPatches});
  add({.id = "patch-measure", .flag = "--patch-measure", .kind = Kind::choice,
       .choices = {"geometric", "algebraic", "algebraic-normalized"}, .ignore_case = true, .default_text = "geometric",
       .help = "What a face's distance to a torus is, against --tolerance (I-30, docs/FIDELITY.md): geometric (the "
               "Euclidean distance), algebraic (the implicit equation's value |d^2 - r^2|) or algebraic-normalized "
               "(that value over its gradient)",
       .scene_key = "patches.measure", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks, .group = kPatches});
  add({.id = "patch-normal-angle", .flag = "--patch-normal-angle", .kind = Kind::number, .lo = 0, .hi = 90,
       .default_text = "0",
       .help = "Also require a face's normal within this many degrees of its torus's normal (I-31); 0 = distance only",
       .scene_key = "patches.normal_angle", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks,
       .group = kPatches});
  add({.id = "patches-on-unsmoothed", .flag = "--patches-on-unsmoothed", .kind = Kind::flag,
       .help = "Test faces against the tori on the unsmoothed surface (the tori still come from the smoothed one) (I-33)",
       .scene_key = "patches.on_unsmoothed", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks,
       .group = kPatches});
  add({.id = "seed-order", .flag = "--seed-order", .kind = Kind::choice, .choices = {"best-fit-first", "index"},
       .ignore_case = true, .default_text = "best-fit-first",
       .help = "Order in which vertices start patches (I-10): best-fit-first (independent of the "
               "file's numbering) or index (file order)",
       .scene_key = "patches.seed_order", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks, .group = kPatches});
  add({.id = "leftovers", .flag = "--leftovers", .kind = Kind::choice, .choices = {"single", "grow-leftovers"},
       .ignore_case = true, .default_text = "single",
       .help = "Faces no grown patch covers (I-13): single = a one-face patch from the best of its "
               "3 vertex tori; grow-leftovers = grow a patch from it",
       .scene_key = "patches.leftovers", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks, .group = kPatches});
  add({.id = "keep-inaccurate", .flag = "--keep-inaccurate", .kind = Kind::flag,
       .help = "Keep one-face patches that miss the tolerance instead of leaving the face without "
               "a patch (an orphan) (I-14)",
       .scene_key = "patches.keep_inaccurate", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks,
       .group = kPatches});
  add({.id = "weight-neighbourhood", .flag = "--weight-neighbourhood", .kind = Kind::choice,
       .choices = {"vertex-3-ring", "vertex-2-ring", "edge-2-ring"}, .ignore_case = true, .default_text = "vertex-3-ring",
       .help = "Faces around a face whose distinct patches make its weight w(f) (I-15): "
               "vertex-3-ring = faces touching the vertices within 2 edges (73 faces on a regular "
               "mesh, R5); vertex-2-ring = 37 faces (R1); edge-2-ring = 10 faces (R3)",
       .scene_key = "patches.weight_neighbourhood", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks,
       .group = kPatches});
  add({.id = "keep-duplicate-vertices", .flag = "--keep-duplicate-vertices", .kind = Kind::flag,
       .help = "Do not merge vertices with identical coordinates (by default they are merged, "
               "which stitches STL-style triangle soups)",
       .scene_key = "patches.keep_duplicate_vertices", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks,
       .group = kPatches});
  add({.id = "axis-point", .flag = "--axis-point", .kind = Kind::choice, .choices = {"centroid", "aabb-center"},
       .ignore_case = true, .default_text = "centroid",
       .help = "Where the cylinder axis passes (I-19): centroid = area-weighted centre of the "
               "surface; aabb-center = centre of the bounding box",
       .scene_key = "paper.axis_point", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks, .group = kGrid});
  add({.id = "rows", .flag = "--rows", .kind = Kind::integer, .lo = 1, .hi = 1000, .default_text = "11",
       .help = "Grid rows m along the cylinder height (§10)", .scene_key = "paper.rows", .manifest_column = true,
       .commands = kPathCommands, .farm = kToTasks, .group = kGrid});
  add({.id = "columns", .flag = "--columns", .kind = Kind::integer, .lo = 3, .hi = 1000, .default_text = "20",
       .help = "Grid columns n around the axis = number of control points of the curve (§10, §11)",
       .scene_key = "paper.columns", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks, .group = kGrid});
  add({.id = "cell-averaging", .flag = "--cell-averaging", .kind = Kind::choice, .choices = {"mean", "area-weighted"},
       .ignore_case = true, .default_text = "mean",
       .help = "How a cell's weight averages the w(f) of the faces whose centroids fall in it (I-17)",
       .scene_key = "paper.cell_averaging", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks, .group = kGrid});
  add({.id = "empty-columns", .flag = "--empty-columns", .kind = Kind::choice, .choices = {"middle-row", "interpolate"},
       .ignore_case = true, .default_text = "middle-row",
       .help = "Height of a control point in a column without any face (I-21): middle-row, or "
               "interpolate between the nearest non-empty columns",
       .scene_key = "paper.empty_columns", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks, .group = kGrid});
  add({.id = "degree", .flag = "--degree", .kind = Kind::integer, .lo = 2, .hi = 3, .default_text = "3",
       .help = "Degree of the closed B-spline (I-23): 3 = cubic (C2), 2 = quadratic (C1)", .scene_key = "paper.degree",
       .manifest_column = true, .commands = kPathCommands, .farm = kToTasks, .group = kCurve});
  add({.id = "gaze-scale", .flag = "--gaze-scale", .kind = Kind::number, .lo = 0, .hi = 1, .default_text = "0.5",
       .help = "s_g: the point looked at follows the curve's height deviation times this (§13.1)",
       .scene_key = "paper.gaze_scale", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks, .group = kCurve});
  add({.id = "position-scale", .flag = "--position-scale", .kind = Kind::number, .lo = 0, .hi = 1, .default_text = "0.25",
       .help = "s_p: the camera follows the curve's height deviation times this (§13.1)", .scene_key = "paper.position_scale",
       .manifest_column = true, .commands = kPathCommands, .farm = kToTasks, .group = kCurve});
  add({.id = "height-reference", .flag = "--height-reference", .kind = Kind::choice, .choices = {"mid-height", "curve-mean"},
       .ignore_case = true, .default_text = "mid-height",
       .help = "Height the deviations are scaled about (I-25): mid-height of the cylinder, or the "
               "mean height of the curve",
       .scene_key = "paper.height_reference", .manifest_column = true, .commands = kPathCommands, .farm = kToTasks,
       .group = kCurve});
  add({.id = "gaze-radius", .flag = "--gaze-radius", .kind = Kind::choice, .choices = {"cylinder", "scaled"},
       .ignore_case = true, .default_text = "cylinder",
       .help = "Radius of the path looked at (I-26): cylinder = r, scaled = gaze-scale * r", .scene_key = "paper.gaze_radius",
       .manifest_column = true, .commands = kPathCommands, .farm = kToTasks, .group = kCurve});
  return r;
}

bool parse_number(const std::string& text, double& value) {
  if (text.empty()) return false;
  const char* begin = text.data();
  const char* end = begin + text.size();
  if (*begin == '+') ++begin;
  const auto [p, ec] = std::from_chars(begin, end, value);
  return ec == std::errc() && p == end && std::isfinite(value);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string choice_list_text(const Option& o) {
  std::string list;
  for (std::size_t i = 0; i < o.choices.size(); ++i)
    list += (i == 0 ? "" : i + 1 == o.choices.size() ? " or " : ", ") + std::string(o.choices[i]);
  return list;
}

bool is_choice(const Option& o, const std::string& text) {
  const std::string t = o.ignore_case ? lower(text) : text;
  return std::find(o.choices.begin(), o.choices.end(), t) != o.choices.end();
}

std::string range_text(const Option& o) { return number_text(o.lo) + " and " + number_text(o.hi); }

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out(1);
  for (const char c : text) {
    if (c == ',') out.emplace_back();
    else if (c != ' ') out.back() += c;
  }
  return out;
}

}  // namespace

const std::vector<Option>& registry() {
  static const std::vector<Option> rows = make_registry();
  return rows;
}

const Option& option(std::string_view id) {
  for (const Option& o : registry())
    if (o.id == id) return o;
  throw std::logic_error("meshtour: no option '" + std::string(id) + "' in the registry");
}

const Option* option_for_scene_key(std::string_view key) {
  for (const Option& o : registry())
    if (!o.scene_key.empty() && o.scene_key == key) return &o;
  return nullptr;
}

std::string number_text(double value) {
  char text[64];
  if (value == std::floor(value) && std::fabs(value) < 1e15) {
    std::snprintf(text, sizeof text, "%lld", static_cast<long long>(value));
    return text;
  }
  for (int digits = 6; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, value);
    double back = 0;
    if (parse_number(text, back) && back == value) break;
  }
  return text;
}

bool parse_pixel_size(std::string_view text, int& width, int& height) {
  const std::size_t x = text.find_first_of("xX");
  if (x == std::string_view::npos) return false;
  const auto whole = [](std::string_view part, int& out) {
    if (part.empty() || part.size() > 9) return false;
    const auto [p, ec] = std::from_chars(part.data(), part.data() + part.size(), out);
    return ec == std::errc() && p == part.data() + part.size() && out >= 0;
  };
  return whole(text.substr(0, x), width) && whole(text.substr(x + 1), height);
}

namespace {

std::string check_as(const Option& o, Kind kind, const std::string& text) {
  double v = 0;
  switch (kind) {
    case Kind::integer: {
      long long i = 0;
      const auto [p, ec] = std::from_chars(text.data() + (text.starts_with('+') ? 1 : 0), text.data() + text.size(), i);
      if (text.empty() || ec != std::errc() || p != text.data() + text.size())
        return "must be a whole number between " + range_text(o) + ", got '" + text + "'";
      if (i < o.lo || i > o.hi) return "must be between " + range_text(o) + ", got " + text;
      return {};
    }
    case Kind::number:
      if (!parse_number(text, v)) return "'" + text + "' is not a number";
      if (!(v >= o.lo && v <= o.hi)) return "must be between " + range_text(o) + ", got " + text;
      return {};
    case Kind::positive:
      if (!parse_number(text, v)) return "'" + text + "' is not a number";
      if (!(v > 0.0)) return "must be greater than 0, got " + text;
      return {};
    case Kind::choice:
      if (!is_choice(o, text)) return "'" + text + "' is not one of " + choice_list_text(o);
      return {};
    case Kind::choice_list:
      for (const std::string& item : split_list(text))
        if (!is_choice(o, item)) return "has '" + item + "'; the choices are " + choice_list_text(o);
      return {};
    case Kind::number_or_choice:
      if (is_choice(o, text)) return {};
      if (!parse_number(text, v) || !(v >= o.lo && v <= o.hi))
        return "must be " + choice_list_text(o) + " or a number between " + range_text(o) + ", got '" + text + "'";
      return {};
    case Kind::frame_selection:
      try {
        (void)parse_frame_range(text, 1'000'000'000);
      } catch (const std::exception& e) {
        return e.what();
      }
      return {};
    case Kind::text:
      if (text.empty()) return "must not be empty";
      return {};
    case Kind::existing_file:
      return {};  // checked where the file is opened, with the reader's own message
    case Kind::flag:
      if (text != "true" && text != "false") return "must be true or false, got '" + text + "'";
      return {};
    case Kind::size: {
      int w = 0, h = 0;
      if (!parse_pixel_size(text, w, h)) return "must be WIDTHxHEIGHT in pixels, e.g. 640x360, got '" + text + "'";
      if (w < o.lo || w > o.hi || h < o.lo || h > o.hi || (o.even_sides && (w % 2 != 0 || h % 2 != 0)))
        return "must have " + std::string(o.even_sides ? "even " : "") + "sides between " + range_text(o) + " pixels, got " + text;
      return {};
    }
    case Kind::memory_size:
      try {
        (void)parse_memory_size(text);
      } catch (const std::exception& e) {
        return e.what();
      }
      return {};
    case Kind::up_direction:
      if (is_auto_up(text)) return {};  // decided on the loaded model (mesh/up_axis.h)
      try {
        (void)UpDirection::parse(text);
      } catch (const std::exception& e) {
        return e.what();
      }
      return {};
  }
  return {};
}

}  // namespace

std::string check_value(const Option& o, const std::string& text) { return check_as(o, o.kind, text); }

std::string check_value(const Option& o, const std::string& text, Command command) {
  return check_as(o, o.kind_in(command), text);
}

std::string_view Option::help_in(Command command) const {
  for (const CommandMeaning& m : meanings)
    if ((m.commands & command) && !m.help.empty()) return m.help;
  return help;
}

std::string_view Option::default_in(Command command) const {
  for (const CommandMeaning& m : meanings)
    if ((m.commands & command) && !m.default_text.empty()) return m.default_text;
  return default_text;
}

Kind Option::kind_in(Command command) const {
  for (const CommandMeaning& m : meanings)
    if ((m.commands & command) && m.kind) return *m.kind;
  return kind;
}

std::string normalize_value(const Option& o, const std::string& text) {
  switch (o.kind) {
    case Kind::choice:
    case Kind::number_or_choice:
      return o.ignore_case || o.kind == Kind::number_or_choice ? lower(text) : text;
    case Kind::choice_list: {
      std::string out;
      for (const std::string& item : split_list(text)) out += (out.empty() ? "" : ",") + (o.ignore_case ? lower(item) : item);
      return out;
    }
    default:
      return text;
  }
}

std::string check_value_for_codec(const Option& o, const std::string& text, std::string_view codec) {
  if (std::string problem = check_value(o, text); !problem.empty()) return problem;
  if (!o.codec_dependent) return {};
  const VideoCodec known = parse_video_codec(codec);
  const std::optional<CrfRange> c = crf_range(known);
  if (!c) return "does not apply to " + std::string(codec) + " (it takes none)";
  const long long v = std::stoll(text);
  if (v < c->lo || v > c->hi)
    return "must be between " + std::to_string(c->lo) + " and " + std::to_string(c->hi) + " for " + std::string(codec) + ", got " + text;
  return {};
}

Target target(const Option& o) {
  if (o.scene_key.starts_with("patches.") || o.scene_key.starts_with("paper.")) return Target::path_search;
  if (!o.scene_key.empty() || o.id == "seconds") return Target::scene;  // --seconds: the tour length in other units
  static constexpr std::string_view kVideo[] = {"poster", "poster-size", "caption", "caption-position", "caption-size", "font", "title-card"};
  if (std::find(std::begin(kVideo), std::end(kVideo), o.id) != std::end(kVideo)) return Target::video;
  return Target::command;
}

std::string codec_ranges_text(const Option& o) {
  std::string text;
  if (!o.codec_dependent) return text;
  for (const VideoCodecInfo& c : video_codecs())
    if (c.crf)
      text += (text.empty() ? "" : "; ") + std::string(c.name) + " " + std::to_string(c.crf->lo) + ".." + std::to_string(c.crf->hi) +
              ", default " + std::to_string(c.crf->fallback);
  return text;
}

std::vector<std::string> forwarded_args(const Values& values, FarmPass pass, Command command) {
  std::vector<std::string> out;
  for (const Option& o : registry()) {
    if (!(o.farm & pass) || !(o.commands & command)) continue;
    const auto it = values.find(o.id);
    if (it == values.end()) continue;
    if (o.kind == Kind::flag) {
      if (it->second == "true") out.emplace_back(o.flag_in(command));
      continue;
    }
    out.emplace_back(o.flag_in(command));
    out.push_back(it->second);
  }
  return out;
}

std::string_view command_name(Command c) {
  switch (c) {
    case tour: return "tour";
    case render: return "render";
    case batch: return "batch";
    case farm: return "farm slurm";
    case path: return "path";
    case evaluate: return "evaluate";
    case encode: return "encode";
    case info: return "info";
  }
  return "?";
}

std::string misplaced_flag_hint(std::string_view command, std::string_view flag) {
  unsigned bit = 0;
  for (const Command c : kAllCommands)
    if (command_name(c) == command || (c == farm && command == "slurm")) bit = c;
  // The commands that take a row under this name (several rows may share it: --json, --samples).
  std::vector<std::string_view> owners;
  for (const Command c : kAllCommands)
    for (const Option& o : registry())
      if ((o.commands & c) && o.flag_in(c) == flag && std::find(owners.begin(), owners.end(), command_name(c)) == owners.end())
        owners.push_back(command_name(c));
  std::string list;
  for (std::size_t k = 0; k < owners.size(); ++k)
    list += std::string(k == 0 ? "" : k + 1 == owners.size() ? " and " : ", ") + std::string(owners[k]);
  for (const Option& o : registry()) {
    if (o.flag != flag && (o.alt_flag.empty() || o.alt_flag != flag)) continue;
    if (!(o.commands & bit)) continue;
    const std::string_view here = o.flag_in(static_cast<Command>(bit));
    if (here != flag)  // the same setting under this command's own name
      return std::string(command) + " takes it as " + std::string(here) + " (" + std::string(flag) + " is " + list + "'s name)";
  }
  return list.empty() ? "" : std::string(flag) + " is an option of " + list + ", not of " + std::string(command);
}

namespace {
std::string kind_text(const Option& o, Kind kind) {
  switch (kind) {
    case Kind::integer: return "integer " + number_text(o.lo) + "..." + number_text(o.hi);
    case Kind::number: return "number " + number_text(o.lo) + "..." + number_text(o.hi);
    case Kind::positive: return "number > 0";
    case Kind::choice: return "one of " + choice_list_text(o);
    case Kind::choice_list: return "comma-separated list of " + choice_list_text(o);
    case Kind::number_or_choice: return choice_list_text(o) + " or number " + number_text(o.lo) + "..." + number_text(o.hi);
    case Kind::frame_selection: return "frame selection (all, A, A-B, A-B:S, lists)";
    case Kind::text: return "text";
    case Kind::existing_file: return "existing file";
    case Kind::flag: return "flag";
    case Kind::size:
      return "WIDTHxHEIGHT, " + std::string(o.even_sides ? "even " : "") + "sides " + number_text(o.lo) + "..." + number_text(o.hi);
    case Kind::memory_size: return "bytes, or a number with K, M, G or T (1M...1000000T)";
    case Kind::up_direction: return "x, y, z, -x, -y, -z, a vector a,b,c, longest-aabb, pca or auto";
  }
  return "";
}

std::string one_line(std::string_view text) {
  std::string s(text);
  std::replace(s.begin(), s.end(), '\n', ' ');
  std::string out;
  for (const char c : s) {
    if (c == '|') out += "\\|";
    else out += c;
  }
  return out;
}

std::string command_list(unsigned commands) {
  std::string list;
  for (const Command c : kAllCommands)
    if (commands & c) list += (list.empty() ? "" : ", ") + std::string(command_name(c));
  return list;
}
}  // namespace

std::string options_markdown() {
  std::string md =
      "# meshtour options\n\n"
      "Generated from the option registry (`options/option_registry.cpp`) by `meshtour options > docs/OPTIONS.md`;\n"
      "do not edit by hand (a test fails when this file is stale). Every option is declared once there:\n"
      "its command-line flag, range, help, scene-file key and batch-manifest column all come from that row.\n\n"
      "Columns: **commands** that take it; **scene key** in a scene file (`meshtour-scene/1`); **column**\n"
      "= also a batch-manifest column (named by the option's id); **farm** = what `farm slurm` passes it to.\n\n"
      "## Flags of each command\n\n"
      "Besides `-h`/`--help`; `meshtour <command> --help` lists the same (a test compares them).\n\n";
  for (const Command c : kAllCommands) {
    md += "- `meshtour " + std::string(command_name(c)) + "`:";
    bool first = true;
    for (const Option& o : registry()) {
      if (!(o.commands & c)) continue;
      md += first ? " " : ", ";
      first = false;
      // append(), not "`" + std::string(...): GCC 12 warns falsely (-Wrestrict) about the latter.
      if (!o.short_flag.empty()) md.append("`").append(o.short_flag).append("` ");
      md.append("`").append(o.flag_in(c)).append("`");
    }
    md += "\n";
  }
  md += "\n";
  for (const Option& o : registry()) {
    md += "## `" + std::string(o.flag) + "`";
    if (!o.short_flag.empty()) md += " (`" + std::string(o.short_flag) + "`)";
    if (o.alt_flag_commands) md += " (`" + std::string(o.alt_flag) + "` in render)";
    md += " — " + std::string(o.id) + "\n\n" + one_line(o.help) + "\n\n";
    if (!o.long_help.empty()) md += one_line(o.long_help) + "\n\n";
    for (const CommandMeaning& m : o.meanings) {
      md += "- in " + command_list(m.commands) + ":";
      if (!m.help.empty()) md += " " + one_line(m.help);
      if (!m.default_text.empty()) md += " (default " + std::string(m.default_text) + ")";
      if (m.kind) md += " (" + kind_text(o, *m.kind) + ")";
      md += "\n";
    }
    if (!o.meanings.empty()) md += "\n";
    std::string farm;
    if (o.farm & render_tasks) farm += "render tasks";
    if (o.farm & encode_job) farm += std::string(farm.empty() ? "" : ", ") + "encode job";
    if (o.farm & batch_tasks) farm += std::string(farm.empty() ? "" : ", ") + "batch tasks";
    std::string commands = command_list(o.commands);
    if (o.required) commands += " (required in " + command_list(o.required) + ")";
    md += "| type | default | commands | scene key | column | farm |\n|---|---|---|---|---|---|\n";
    md += "| " + kind_text(o, o.kind) + " | " + (o.default_text.empty() ? "—" : std::string(o.default_text)) + " | " + commands +
          " | " + (o.scene_key.empty() ? "—" : "`" + std::string(o.scene_key) + "`") + " | " +
          (o.manifest_column ? "`" + std::string(o.id) + "`" : "—") + " | " + (farm.empty() ? "—" : farm) + " |\n";
    if (o.codec_dependent)
      for (const VideoCodecInfo& c : video_codecs())
        if (c.crf)
          md += "\n- " + std::string(c.name) + ": " + std::to_string(c.crf->lo) + "..." + std::to_string(c.crf->hi) + ", default " +
                std::to_string(c.crf->fallback);
    md += o.codec_dependent ? "\n\n" : "\n";
  }
  return md;
}

}  // namespace meshtour::options
