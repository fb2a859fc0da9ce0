#include "cli/path_options.h"

#include "core/error.h"

namespace meshtour::cli {

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

PaperPathOptions paper_path_options(const options::Values& values, PaperPathOptions p) {
  SurfaceOptions& s = p.surface;
  for (const auto& [id, text] : values) {
    if (id == "tolerance") s.tolerance = std::stod(text);
    else if (id == "smoothing") s.smoothing = parse_smoothing_method(text);
    else if (id == "smoothing-strength") s.smoothing_strength = std::stod(text);
    else if (id == "curvature-fit") s.curvature_fit = parse_curvature_fit(text);
    else if (id == "kappa-min") s.kappa_min = std::stod(text);
    else if (id == "face-samples") s.face_samples = parse_face_samples(text);
    else if (id == "seed-order") s.seed_order = parse_seed_order(text);
    else if (id == "leftovers") s.leftovers = parse_leftover_mode(text);
    else if (id == "keep-inaccurate") s.keep_inaccurate_patches = text == "true";
    else if (id == "weight-neighbourhood") s.weight_neighbourhood = parse_weight_neighbourhood(text);
    else if (id == "keep-duplicate-vertices") s.merge_duplicate_vertices = text != "true";
    else if (id == "axis-point") p.axis_point = text == "aabb-center" ? AxisPointMode::aabb_center : AxisPointMode::surface_centroid;
    else if (id == "rows") p.rows = std::stoi(text);
    else if (id == "columns") p.columns = std::stoi(text);
    else if (id == "cell-averaging") p.cell_averaging = text == "area-weighted" ? CellAveraging::area_weighted : CellAveraging::mean;
    else if (id == "empty-columns") p.empty_columns = text == "interpolate" ? EmptyColumnMode::interpolate : EmptyColumnMode::middle_row;
    else if (id == "degree") p.degree = std::stoi(text);
    else if (id == "gaze-scale") p.gaze_scale = std::stod(text);
    else if (id == "position-scale") p.position_scale = std::stod(text);
    else if (id == "height-reference") p.height_reference = text == "curve-mean" ? HeightReference::curve_mean : HeightReference::mid_height;
    else if (id == "gaze-radius") p.gaze_radius = text == "scaled" ? GazeRadiusMode::scaled : GazeRadiusMode::cylinder;
  }
  return p;
}

}  // namespace meshtour::cli
