// §3–§8 in order: clean-up and normalization, smoothing, curvature, tori and patches, weights.
#include "pathgen/surface.h"
#include "pathgen/stage_timer.h"

#include <tbb/global_control.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "core/error.h"
#include "pathgen/curvature.h"
#include "pathgen/patches.h"
#include "pathgen/smoothing.h"
#include "pathgen/surface_mesh.h"
#include "pathgen/weights.h"

namespace meshtour {
namespace {

using namespace surface_detail;

template <class Enum, std::size_t N>
Enum parse_enum(std::string_view text, const char* option, const std::array<std::pair<const char*, Enum>, N>& names) {
  std::string accepted;
  for (const auto& [name, value] : names) {
    if (text == name) return value;
    accepted += (accepted.empty() ? "" : ", ") + std::string(name);
  }
  throw InputError("unknown " + std::string(option) + " '" + std::string(text) + "' (use one of: " + accepted + ")");
}

template <class Enum, std::size_t N>
std::string enum_name(Enum value, const std::array<std::pair<const char*, Enum>, N>& names) {
  for (const auto& [name, v] : names)
    if (v == value) return name;
  return "?";
}

constexpr std::array<std::pair<const char*, SmoothingMethod>, 4> kSmoothingNames{{{"implicit", SmoothingMethod::implicit},
                                                                                  {"none", SmoothingMethod::none},
                                                                                  {"taubin", SmoothingMethod::taubin},
                                                                                  {"pmp-default", SmoothingMethod::pmp_default}}};
constexpr std::array<std::pair<const char*, CurvatureFit>, 2> kFitNames{{{"cubic", CurvatureFit::cubic},
                                                                         {"quadratic", CurvatureFit::quadratic}}};
constexpr std::array<std::pair<const char*, FaceSamples>, 3> kSampleNames{{{"seven", FaceSamples::seven},
                                                                           {"vertices", FaceSamples::vertices},
                                                                           {"edges-4", FaceSamples::edges4}}};
constexpr std::array<std::pair<const char*, ToleranceUnit>, 3> kToleranceUnitNames{
    {{"diagonal", ToleranceUnit::diagonal},
     {"box-extent", ToleranceUnit::box_extent},
     {"box-half-extent", ToleranceUnit::box_half_extent}}};
constexpr std::array<std::pair<const char*, PatchMeasure>, 3> kMeasureNames{
    {{"geometric", PatchMeasure::geometric},
     {"algebraic", PatchMeasure::algebraic},
     {"algebraic-normalized", PatchMeasure::algebraic_normalized}}};
constexpr std::array<std::pair<const char*, SeedOrder>, 2> kSeedNames{{{"best-fit-first", SeedOrder::best_fit_first},
                                                                       {"index", SeedOrder::index}}};
constexpr std::array<std::pair<const char*, LeftoverMode>, 2> kLeftoverNames{{{"single", LeftoverMode::single},
                                                                              {"grow-leftovers", LeftoverMode::grow}}};
constexpr std::array<std::pair<const char*, WeightNeighbourhood>, 3> kWeightNames{
    {{"vertex-3-ring", WeightNeighbourhood::vertex_3_ring},
     {"vertex-2-ring", WeightNeighbourhood::vertex_2_ring},
     {"edge-2-ring", WeightNeighbourhood::edge_2_ring}}};

void validate(const SurfaceOptions& o, std::size_t input_vertices) {
  if (!(o.tolerance > 0.0))
    throw InputError("the patch tolerance must be a positive number (got " + std::to_string(o.tolerance) +
                     "; the default is 1e-3 of the model's diagonal)");
  if (!(o.smoothing_strength > 0.0) || !std::isfinite(o.smoothing_strength))
    throw InputError("the smoothing strength must be a positive finite number (got " + std::to_string(o.smoothing_strength) +
                     "; the default is 1)");
  if (!(o.kappa_min > 0.0) || !std::isfinite(o.kappa_min))
    throw InputError("the curvature clamp kappa_min must be a positive finite number (default 1e-6)");
  if (o.threads < 0) throw InputError("the thread count must be 0 (automatic) or positive");
  if (!o.exact_normals.empty() && o.exact_normals.size() != input_vertices)
    throw InputError("exact_normals must hold one normal per input vertex");
  if (!o.exact_differential.empty() && o.exact_differential.size() != input_vertices)
    throw InputError("exact_differential must hold one entry per input vertex");
  for (std::uint32_t v : o.seed_vertices)
    if (v >= input_vertices) throw InputError("seed vertex " + std::to_string(v) + " does not exist in the mesh");
}

SurfaceAnalysis run(const TriangleMesh& input, const SurfaceOptions& options) {
  SurfaceAnalysis result;
  StageTimer clock(result.stage_seconds);

  // §3: clean-up, topology, first normalization. OpenMesh's verdict on the faces (which ones it
  // refuses as non-manifold) takes a sequential pass over 1M faces; it runs beside the
  // normalization and smoothing, which use the flat adjacency built from the same faces. In the
  // rare case that it refuses faces, they are repaired and everything after §3 step 1 is redone.
  SurfaceMesh mesh = prepare_mesh(input, options, result.cleanup);
  std::vector<std::size_t> refused;
  // The check runs in an arena of its own, so that threads waiting inside the parallel loops of
  // the main work cannot pick it up (that would stall those loops until it finishes).
  // No slot is reserved for the calling thread, so a worker can take the check at once; if none
  // is free (one thread allowed), the waiting thread runs it itself.
  tbb::task_arena side_arena(1, 0);
  tbb::task_group openmesh_check;
  side_arena.execute([&] { openmesh_check.run([&] { refused = openmesh_refused_faces(mesh); }); });  // reads triangles only
  const auto wait_for_check = [&] { side_arena.execute([&] { openmesh_check.wait(); }); };
  // Every exit, including an exception, first waits inside the side arena: the task group's own
  // destructor would wait in the current arena, where nobody may be able to run the check.
  struct WaitOnExit {
    const decltype(wait_for_check)& wait;
    ~WaitOnExit() { wait(); }
  } wait_on_exit{wait_for_check};
  const bool adjacency_ok = build_adjacency(mesh);
  if (!adjacency_ok) {
    wait_for_check();
    if (refused.empty()) throw RuntimeFailure("internal: OpenMesh accepted a face list that uses an edge twice in one direction");
    repair_refused_faces(mesh, refused, result.cleanup);
    refused.clear();
    if (!build_adjacency(mesh)) throw RuntimeFailure("internal: an edge is used twice in one direction after clean-up");
  }
  Eigen::Vector3d center1, center2 = Eigen::Vector3d::Zero();
  double diagonal1 = 1.0, diagonal2 = 1.0;
  std::vector<Eigen::Vector3d> unsmoothed;  // I-33 only
  std::size_t zero_area = 0;
  bool repeat = true;
  while (repeat) {
    repeat = false;
    std::tie(center1, diagonal1) = normalize_positions(mesh.positions);
    zero_area = 0;
    for (double a : face_areas(mesh.positions, mesh.triangles)) zero_area += a < kDegenerateArea ? 1 : 0;
    if (zero_area == mesh.face_count())
      throw InputError("the mesh has no face with non-zero area (all " + std::to_string(zero_area) +
                       " faces are degenerate: their corners are collinear or coincide)");
    result.mean_edge_length = mean_edge_length(mesh);
    clock.done("normalize");

    // §4: smoothing, then the second normalization (I-1). `none` leaves the positions untouched.
    if (options.smoothing != SmoothingMethod::none) {
      if (options.patches_on_unsmoothed) unsmoothed = mesh.positions;
      const SmoothingResult s = smooth(mesh, options, result.mean_edge_length);
      result.smoothing_dt = s.dt;
      result.smoothing_iterations = s.iterations;
      std::tie(center2, diagonal2) = normalize_positions(mesh.positions);
      // I-33: the unsmoothed surface in the smoothed surface's frame, where the tori live.
      for (auto& p : unsmoothed) p = (p - center2) / diagonal2;
    }
    wait_for_check();
    if (!refused.empty()) {
      // Start again from the prepared mesh with the refused faces repaired (the stage times
      // then include both passes).
      CleanupCounts counts;
      mesh = prepare_mesh(input, options, counts);
      repair_refused_faces(mesh, refused, counts);
      if (!build_adjacency(mesh)) throw RuntimeFailure("internal: an edge is used twice in one direction after clean-up");
      result.cleanup = counts;
      refused.clear();
      repeat = true;
      result.stage_seconds.clear();
      continue;
    }
    clock.done("smooth");
  }
  finish_cleanup(mesh, result.cleanup, result.cleanup_notes);
  result.cleanup.zero_area_faces = zero_area;
  if (zero_area)
    result.cleanup_notes.push_back("kept " + std::to_string(zero_area) + (zero_area == 1 ? " face" : " faces") +
                                   " with zero area (no normal, no smoothing weight)");
  // model = d1·(d2·p + c2) + c1
  result.scale = diagonal1 * diagonal2;
  result.offset = diagonal1 * center2 + center1;

  // §5: normals and principal curvatures (or the exact data of a test hook).
  if (!options.exact_differential.empty()) {
    result.differential.resize(mesh.vertex_count());
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
      result.differential[v] = options.exact_differential[mesh.input_vertex[v]];
  } else {
    std::vector<Eigen::Vector3d> normals;
    if (!options.exact_normals.empty()) {
      normals.resize(mesh.vertex_count());
      for (std::size_t v = 0; v < mesh.vertex_count(); ++v) normals[v] = options.exact_normals[mesh.input_vertex[v]];
    } else {
      normals = vertex_normals(mesh);
    }
    result.differential = principal_curvatures(mesh, normals, options.curvature_fit);
  }
  clock.done("curvature");

  // §6–§7: tori, seed order, decomposition.
  result.vertex_torus = vertex_tori(mesh, result.differential, options.kappa_min);
  std::vector<std::uint32_t> order;
  if (options.seed_order == SeedOrder::best_fit_first) {
    order = best_fit_first_order(mesh, seed_errors(mesh, result.vertex_torus));
  } else {
    // The file's vertex order (vertices are stored in Morton order internally).
    order.resize(mesh.vertex_count());
    for (std::size_t v = 0; v < order.size(); ++v) order[v] = static_cast<std::uint32_t>(v);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return mesh.input_vertex[a] < mesh.input_vertex[b]; });
  }
  std::vector<std::uint32_t> forced_seeds;
  if (!options.seed_vertices.empty()) {
    // Input vertex → cleaned vertex (the first cleaned vertex that came from it).
    std::vector<std::int64_t> cleaned(input.positions.size(), -1);
    for (std::size_t v = mesh.vertex_count(); v-- > 0;) cleaned[mesh.input_vertex[v]] = static_cast<std::int64_t>(v);
    for (std::uint32_t v : options.seed_vertices) {
      if (cleaned[v] < 0) throw InputError("seed vertex " + std::to_string(v) + " was removed by clean-up (it is unused)");
      forced_seeds.push_back(static_cast<std::uint32_t>(cleaned[v]));
    }
  }
  Decomposition d = decompose(mesh, result.vertex_torus, order, forced_seeds, options, unsmoothed.empty() ? nullptr : &unsmoothed);
  result.face_patch = std::move(d.face_patch);
  result.patches = std::move(d.patches);
  result.patch_count = static_cast<int>(result.patches.size());
  result.grown_patches = d.grown;
  result.single_face_patches = d.single;
  result.orphans = d.orphans;
  result.largest_patch = d.largest;
  clock.done("patches");

  // §8.
  result.face_weight = face_weights(mesh, result.face_patch, result.patch_count, options.weight_neighbourhood);
  clock.done("weights");

  result.positions = std::move(mesh.positions);
  result.triangles = std::move(mesh.triangles);
  result.input_vertex = std::move(mesh.input_vertex);
  result.input_face = std::move(mesh.input_face);
  return result;
}

}  // namespace

std::string to_string(SmoothingMethod value) { return enum_name(value, kSmoothingNames); }
std::string to_string(CurvatureFit value) { return enum_name(value, kFitNames); }
std::string to_string(FaceSamples value) { return enum_name(value, kSampleNames); }
std::string to_string(ToleranceUnit value) { return enum_name(value, kToleranceUnitNames); }
std::string to_string(PatchMeasure value) { return enum_name(value, kMeasureNames); }
std::string to_string(SeedOrder value) { return enum_name(value, kSeedNames); }
std::string to_string(LeftoverMode value) { return enum_name(value, kLeftoverNames); }
std::string to_string(WeightNeighbourhood value) { return enum_name(value, kWeightNames); }
SmoothingMethod parse_smoothing_method(std::string_view text) { return parse_enum(text, "smoothing method", kSmoothingNames); }
CurvatureFit parse_curvature_fit(std::string_view text) { return parse_enum(text, "curvature fit", kFitNames); }
FaceSamples parse_face_samples(std::string_view text) { return parse_enum(text, "face sample set", kSampleNames); }
ToleranceUnit parse_tolerance_unit(std::string_view text) { return parse_enum(text, "tolerance unit", kToleranceUnitNames); }
PatchMeasure parse_patch_measure(std::string_view text) { return parse_enum(text, "patch measure", kMeasureNames); }
SeedOrder parse_seed_order(std::string_view text) { return parse_enum(text, "seed order", kSeedNames); }
LeftoverMode parse_leftover_mode(std::string_view text) { return parse_enum(text, "leftover mode", kLeftoverNames); }
WeightNeighbourhood parse_weight_neighbourhood(std::string_view text) {
  return parse_enum(text, "weight neighbourhood", kWeightNames);
}

SurfaceAnalysis analyze_surface(const TriangleMesh& mesh, const SurfaceOptions& options) {
  validate(options, mesh.positions.size());
  if (options.threads > 0) {
    // Every parallel loop inside runs in this arena; results do not depend on its size. More
    // threads than TBB allows would only make it print a warning, so ask for at most that many.
    const auto allowed = static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
    tbb::task_arena arena(std::max(1, std::min(options.threads, allowed)));
    return arena.execute([&] { return run(mesh, options); });
  }
  return run(mesh, options);
}

}  // namespace meshtour
