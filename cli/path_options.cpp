#include "cli/path_options.h"

#include <algorithm>
#include <cctype>
#include <sstream>

#include "core/error.h"

namespace meshtour::cli {
namespace {

std::string number_text(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

// An option whose text is parsed by `parse` into `target` (a meshtour enum). The set of accepted
// names is checked by CLI11 first, so a typo is reported as a usage error listing the choices.
template <typename T, typename Parse, typename Name>
CLI::Option* add_choice(CLI::App& cmd, const std::string& flag, T& target, Parse parse, Name name,
                        std::vector<std::string> choices, const std::string& help) {
  return cmd
      .add_option_function<std::string>(
          flag,
          [&target, parse](std::string text) {
            // IsMember matched without case; the parsers want the canonical (lower-case) name.
            std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
            target = parse(text);
          },
          help)
      ->check(CLI::IsMember(std::move(choices), CLI::ignore_case))
      ->default_str(name(target))
      ->type_name("NAME");
}

// CLI11's own numeric range checks print their bounds with %f (0.000000 to 1797...); these say
// the bound as a user would write it.
bool parse_double(const std::string& text, double& value) {
  try {
    std::size_t used = 0;
    value = std::stod(text, &used);
    return used == text.size();
  } catch (const std::exception&) {
    return false;
  }
}

CLI::Validator positive_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0.0;
        if (!parse_double(text, v)) return "'" + text + "' is not a number";
        if (!(v > 0.0)) return "must be greater than 0, got " + text;
        return {};
      },
      "POSITIVE");
}

CLI::Validator number_between(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        double v = 0.0;
        if (!parse_double(text, v)) return "'" + text + "' is not a number";
        if (!(v >= lo && v <= hi)) return "must be between " + number_text(lo) + " and " + number_text(hi) + ", got " + text;
        return {};
      },
      "[" + number_text(lo) + " - " + number_text(hi) + "]");
}

template <typename T>
CLI::Option* add_number(CLI::App& cmd, const std::string& flag, T& target, const std::string& help) {
  return cmd.add_option(flag, target, help)->default_str(number_text(target));
}

}  // namespace

const char* const kPaperUpHelp =
    "Up direction of the model = axis of the bounding cylinder the camera circles (I-18): "
    "x, y, z, -x, -y, -z, a vector such as 0,1,0.2, 'longest-aabb' (longest side of the "
    "bounding box) or 'pca' (principal axis of the surface)";

CLI::Validator up_direction_validator() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        try {
          UpDirection::parse(text);
        } catch (const InputError& e) {
          return e.what();
        }
        return {};
      },
      "AXIS");
}

void add_paper_path_options(CLI::App& cmd, PaperPathOptions& options) {
  SurfaceOptions& s = options.surface;
  const std::string patches = "Toroidal patches (ALGORITHM.md §3-§8)";
  const std::string grid = "Cylinder and grid (§9-§11)";
  const std::string curve = "Curve and camera (§12-§13)";

  add_number(cmd, "--tolerance", s.tolerance,
             "Patch tolerance epsilon: largest distance between a face and the torus of its patch, "
             "in units of the model's bounding-box diagonal. Smaller = more, smaller patches")
      ->check(positive_number())
      ->group(patches);
  add_choice(cmd, "--smoothing", s.smoothing, parse_smoothing_method,
             [](SmoothingMethod m) { return to_string(m); }, {"implicit", "none", "taubin", "pmp-default"},
             "Smoothing before curvature estimation (I-2, I-3): implicit = one backward-Euler "
             "cotangent-Laplacian step with dt = strength * (mean edge length)^2; none; taubin "
             "(lambda|mu, 10 iterations); pmp-default (dt = 1e-3, strong)")
      ->group(patches);
  add_number(cmd, "--smoothing-strength", s.smoothing_strength,
             "c_s of dt = c_s * (mean edge length)^2 for --smoothing implicit (I-2). 1 halves "
             "wiggles about 6 edges long; 0.25-0.5 keeps more detail")
      ->check(positive_number())
      ->group(patches);
  add_choice(cmd, "--curvature-fit", s.curvature_fit, parse_curvature_fit,
             [](CurvatureFit m) { return to_string(m); }, {"cubic", "quadratic"},
             "Principal-curvature fit over the 1-ring (I-4): cubic = Goldfeather-Interrante with "
             "positions and normals; quadratic = the 3 quadratic terms only")
      ->group(patches);
  add_number(cmd, "--kappa-min", s.kappa_min,
             "Smallest curvature magnitude used for a torus, per diagonal (I-9): flat and "
             "cylindrical points get radii up to 1/kappa-min")
      ->check(positive_number())
      ->group(patches);
  add_choice(cmd, "--face-samples", s.face_samples, parse_face_samples,
             [](FaceSamples m) { return to_string(m); }, {"seven", "vertices"},
             "Points of a face tested against a torus (I-11): seven = corners, edge midpoints "
             "and centroid; vertices = the 3 corners")
      ->group(patches);
  add_choice(cmd, "--seed-order", s.seed_order, parse_seed_order, [](SeedOrder m) { return to_string(m); },
             {"best-fit-first", "index"},
             "Order in which vertices start patches (I-10): best-fit-first (independent of the "
             "file's numbering) or index (file order)")
      ->group(patches);
  add_choice(cmd, "--leftovers", s.leftovers, parse_leftover_mode, [](LeftoverMode m) { return to_string(m); },
             {"single", "grow-leftovers"},
             "Faces no grown patch covers (I-13): single = a one-face patch from the best of its "
             "3 vertex tori; grow-leftovers = grow a patch from it")
      ->group(patches);
  cmd.add_flag("--keep-inaccurate", s.keep_inaccurate_patches,
               "Keep one-face patches that miss the tolerance instead of leaving the face without "
               "a patch (an orphan) (I-14)")
      ->group(patches);
  add_choice(cmd, "--weight-neighbourhood", s.weight_neighbourhood, parse_weight_neighbourhood,
             [](WeightNeighbourhood m) { return to_string(m); }, {"vertex-3-ring", "vertex-2-ring", "edge-2-ring"},
             "Faces around a face whose distinct patches make its weight w(f) (I-15): "
             "vertex-3-ring = faces touching the vertices within 2 edges (73 faces on a regular "
             "mesh, R5); vertex-2-ring = 37 faces (R1); edge-2-ring = 10 faces (R3)")
      ->group(patches);
  cmd.add_flag("!--keep-duplicate-vertices", s.merge_duplicate_vertices,
               "Do not merge vertices with identical coordinates (by default they are merged, "
               "which stitches STL-style triangle soups)")
      ->group(patches);

  add_choice(cmd, "--axis-point", options.axis_point,
             [](std::string_view t) {
               return t == "aabb-center" ? AxisPointMode::aabb_center : AxisPointMode::surface_centroid;
             },
             [](AxisPointMode m) { return to_string(m); }, {"centroid", "aabb-center"},
             "Where the cylinder axis passes (I-19): centroid = area-weighted centre of the "
             "surface; aabb-center = centre of the bounding box")
      ->group(grid);
  add_number(cmd, "--rows", options.rows, "Grid rows m along the cylinder height (§10)")
      ->check(CLI::Range(1, 1000))
      ->group(grid);
  add_number(cmd, "--columns", options.columns,
             "Grid columns n around the axis = number of control points of the curve (§10, §11)")
      ->check(CLI::Range(3, 1000))
      ->group(grid);
  add_choice(cmd, "--cell-averaging", options.cell_averaging,
             [](std::string_view t) { return t == "area-weighted" ? CellAveraging::area_weighted : CellAveraging::mean; },
             [](CellAveraging m) { return to_string(m); }, {"mean", "area-weighted"},
             "How a cell's weight averages the w(f) of the faces whose centroids fall in it (I-17)")
      ->group(grid);
  add_choice(cmd, "--empty-columns", options.empty_columns,
             [](std::string_view t) { return t == "interpolate" ? EmptyColumnMode::interpolate : EmptyColumnMode::middle_row; },
             [](EmptyColumnMode m) { return to_string(m); }, {"middle-row", "interpolate"},
             "Height of a control point in a column without any face (I-21): middle-row, or "
             "interpolate between the nearest non-empty columns")
      ->group(grid);

  add_number(cmd, "--degree", options.degree,
             "Degree of the closed B-spline (I-23): 3 = cubic (C2), 2 = quadratic (C1)")
      ->check(CLI::IsMember({2, 3}))
      ->group(curve);
  add_number(cmd, "--gaze-scale", options.gaze_scale,
             "s_g: the point looked at follows the curve's height deviation times this (§13.1)")
      ->check(number_between(0.0, 1.0))
      ->group(curve);
  add_number(cmd, "--position-scale", options.position_scale,
             "s_p: the camera follows the curve's height deviation times this (§13.1)")
      ->check(number_between(0.0, 1.0))
      ->group(curve);
  add_choice(cmd, "--height-reference", options.height_reference,
             [](std::string_view t) { return t == "curve-mean" ? HeightReference::curve_mean : HeightReference::mid_height; },
             [](HeightReference m) { return to_string(m); }, {"mid-height", "curve-mean"},
             "Height the deviations are scaled about (I-25): mid-height of the cylinder, or the "
             "mean height of the curve")
      ->group(curve);
  add_choice(cmd, "--gaze-radius", options.gaze_radius,
             [](std::string_view t) { return t == "scaled" ? GazeRadiusMode::scaled : GazeRadiusMode::cylinder; },
             [](GazeRadiusMode m) { return to_string(m); }, {"cylinder", "scaled"},
             "Radius of the path looked at (I-26): cylinder = r, scaled = gaze-scale * r")
      ->group(curve);
}

}  // namespace meshtour::cli
