#pragma once
// Stages §3–§8 of docs/METHOD.md: clean-up, normalization, smoothing, normals and principal
// curvatures, osculating tori, the toroidal-patch decomposition and the per-face weights.
// Everything here is in normalized units (AABB diagonal of the smoothed model = 1).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mesh/mesh.h"
#include "pathgen/torus.h"

namespace meshtour {

/// §4: how the normalized mesh is smoothed before curvature estimation (I-2, I-3).
enum class SmoothingMethod {
  implicit,     ///< one backward-Euler cotangent-Laplacian step, dt = strength·ē² (default)
  none,         ///< positions untouched
  taubin,       ///< Taubin λ|μ, uniform weights, λ = 0.5, μ = −0.53, 10 iterations
  pmp_default,  ///< the implicit step with dt = 1e-3 (PMP's default on a unit-diagonal model)
};
/// §5.3: which height function is fitted (I-4).
enum class CurvatureFit {
  cubic,      ///< Goldfeather–Interrante: 7 unknowns, positions and normals of the 1-ring (default)
  quadratic,  ///< the three quadratic unknowns only
};
/// §7.2: order in which Phase A visits candidate seed vertices (I-10).
enum class SeedOrder {
  best_fit_first,  ///< quantized (e_v, x, y, z, index) keys, ascending (default)
  index,           ///< the file's vertex order (not permutation invariant)
};
/// §7.4: what happens to faces Phase A left uncovered (I-13).
enum class LeftoverMode {
  single,  ///< a patch of its own from the best of its 3 vertex tori, not grown (default)
  grow,    ///< `grow-leftovers`: Phase-A growth from the leftover face, in ascending face order
};
/// §8: which faces around f count toward w(f) (I-15).
/// I-34: the length ε is a fraction of. The specification normalizes to a unit bounding-box diagonal;
/// much geometry code instead scales a model into the cube [-1, 1]³ (largest half-side 1).
enum class ToleranceUnit { diagonal, box_extent, box_half_extent };

enum class WeightNeighbourhood {
  vertex_3_ring,  ///< faces touching the vertex 2-ring of f, R5 (default)
  vertex_2_ring,  ///< faces sharing a vertex with a face that shares a vertex with f, R1
  edge_2_ring,    ///< faces reachable over at most two shared edges, R3
};

std::string to_string(SmoothingMethod value);  ///< "implicit", "none", "taubin", "pmp-default"
std::string to_string(CurvatureFit value);     ///< "cubic", "quadratic"
std::string to_string(ToleranceUnit value);    ///< "diagonal", "box-extent", "box-half-extent"
std::string to_string(FaceSamples value);      ///< "seven", "vertices", "edges-4"
std::string to_string(PatchMeasure value);     ///< "geometric", "algebraic", "algebraic-normalized"
std::string to_string(SeedOrder value);        ///< "best-fit-first", "index"
std::string to_string(LeftoverMode value);     ///< "single", "grow-leftovers"
std::string to_string(WeightNeighbourhood value);  ///< "vertex-3-ring", "vertex-2-ring", "edge-2-ring"
/// Inverses of to_string. \throw InputError naming the accepted values.
SmoothingMethod parse_smoothing_method(std::string_view text);
CurvatureFit parse_curvature_fit(std::string_view text);
ToleranceUnit parse_tolerance_unit(std::string_view text);
FaceSamples parse_face_samples(std::string_view text);
PatchMeasure parse_patch_measure(std::string_view text);
SeedOrder parse_seed_order(std::string_view text);
LeftoverMode parse_leftover_mode(std::string_view text);
WeightNeighbourhood parse_weight_neighbourhood(std::string_view text);

/// Second-order differential data at a vertex (§5.4). κ1 has the smaller magnitude; the sign
/// convention is §1.2's (a sphere with outward normals has negative curvatures).
struct VertexDifferential {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d t1 = Eigen::Vector3d::UnitX();  ///< principal direction of κ1
  Eigen::Vector3d t2 = Eigen::Vector3d::UnitY();  ///< principal direction of κ2
  double k1 = 0.0;
  double k2 = 0.0;
};

/// Options of §3–§8 (defaults as in docs/METHOD.md §2).
struct SurfaceOptions {
  double tolerance = 1e-3;  ///< ε, in `tolerance_unit`s (> 0; +infinity allowed)
  /// I-34 (docs/FIDELITY.md): the unit that reproduces the paper's Tables 1 and 2 on the bunny
  /// and the horse (the specification's diagonal is 2.5 times too coarse on both).
  ToleranceUnit tolerance_unit = ToleranceUnit::box_half_extent;
  SmoothingMethod smoothing = SmoothingMethod::implicit;
  double smoothing_strength = 1.0;  ///< c_s of dt = c_s·ē² (implicit only)
  CurvatureFit curvature_fit = CurvatureFit::cubic;
  double kappa_min = 1e-6;  ///< curvature clamp of §6.2 (I-9)
  FaceSamples face_samples = FaceSamples::seven;
  PatchMeasure patch_measure = PatchMeasure::geometric;  ///< I-30 (docs/FIDELITY.md)
  double patch_normal_angle_deg = 0.0;                   ///< I-31: 0 = distance only
  bool patches_on_unsmoothed = false;                    ///< I-33: test faces on the unsmoothed surface
  SeedOrder seed_order = SeedOrder::best_fit_first;
  LeftoverMode leftovers = LeftoverMode::single;
  /// I-14 alternative: a leftover face whose best vertex torus misses ε keeps that (inaccurate)
  /// single-face patch instead of becoming an orphan.
  bool keep_inaccurate_patches = false;
  WeightNeighbourhood weight_neighbourhood = WeightNeighbourhood::vertex_3_ring;
  /// Merge vertices with identical coordinates before building topology (STL-style soups).
  bool merge_duplicate_vertices = true;
  /// Worker threads; 0 = whatever TBB allows (a tbb::global_control of the caller is respected).
  /// Results are bitwise identical for every thread count.
  int threads = 0;

  // ---- test hooks (§17.3, §17.5); indexed by *input* vertex, empty = not used ---------------
  /// Exact unit normals replacing the estimates of §5.1 (frame normals and neighbour normals).
  std::vector<Eigen::Vector3d> exact_normals;
  /// Exact differential data replacing all of §5 (analytic curvature of test surfaces).
  std::vector<VertexDifferential> exact_differential;
  /// Phase A visits exactly these vertices, in this order, instead of the seed order of §7.2.
  std::vector<std::uint32_t> seed_vertices;
};

/// What clean-up (§3, §1.2) changed; every non-zero count also has a line in cleanup_notes.
struct CleanupCounts {
  std::size_t input_vertices = 0;
  std::size_t input_faces = 0;
  std::size_t non_finite_faces = 0;       ///< faces using a vertex with NaN/infinite coordinates: dropped
  std::size_t merged_vertices = 0;        ///< vertices merged into an identical earlier one
  std::size_t repeated_index_faces = 0;   ///< faces using one vertex twice: dropped
  std::size_t duplicate_faces = 0;        ///< second copies of a face (same 3 vertices): dropped
  std::size_t unreferenced_vertices = 0;  ///< removed
  std::size_t split_faces = 0;            ///< faces OpenMesh refused (non-manifold): split off
  std::size_t zero_area_faces = 0;        ///< kept, but they get no normal and no smoothing weight
  std::size_t components = 0;             ///< connected components (sharing a vertex) after clean-up
  std::size_t boundary_edges = 0;         ///< after clean-up
};

/// One toroidal patch of §7.
struct PatchRecord {
  enum class Kind { grown, single };
  Kind kind = Kind::grown;
  std::uint32_t seed_vertex = 0;  ///< index into SurfaceAnalysis::positions
  Torus torus;
  int face_count = 0;
  bool accurate = true;  ///< false only for patches kept by keep_inaccurate_patches
};

/// Result of §3–§8.
struct SurfaceAnalysis {
  /// The cleaned, normalized and smoothed mesh the later stages work on. Faces keep the input's
  /// order (minus dropped faces); vertices are renumbered along a Morton curve for cache locality
  /// (input_vertex leads back to the file's numbering).
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  /// Maps normalized points back to the input model's units: model = scale * p + offset.
  double scale = 1.0;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();

  std::vector<int> face_patch;      ///< patch id of each face, -1 for an orphan (§7)
  std::vector<double> face_weight;  ///< w(f) of §8
  int patch_count = 0;              ///< T
  int grown_patches = 0;            ///< T_grown
  int single_face_patches = 0;      ///< T_single (Phase-B patches)
  int orphans = 0;
  int largest_patch = 0;
  /// What clean-up did to the input (dropped degenerate faces, merged vertices, ...), one line each.
  std::vector<std::string> cleanup_notes;
  /// Wall time of each stage, in order: {"normalize", s}, {"smooth", s}, ...
  std::vector<std::pair<std::string, double>> stage_seconds;

  // ---- further detail, for diagnostics, debug output and tests ------------------------------
  CleanupCounts cleanup;
  /// Input vertex each vertex of `positions` came from (merged and split vertices included).
  std::vector<std::uint32_t> input_vertex;
  /// Input face each face of `triangles` came from.
  std::vector<std::uint32_t> input_face;
  double mean_edge_length = 0.0;  ///< ē of the normalized mesh before smoothing
  double smoothing_dt = 0.0;      ///< dt of the implicit step (0 for none/taubin)
  int smoothing_iterations = 0;   ///< conjugate-gradient iterations of the slowest coordinate column
  std::vector<VertexDifferential> differential;  ///< §5, per vertex
  std::vector<Torus> vertex_torus;               ///< T_v of §6.2, per vertex
  std::vector<PatchRecord> patches;              ///< indexed by patch id
};

/// Runs §3–§8 on `mesh`, whose up axis plays no role yet.
/// \throw InputError if the mesh has no usable face (empty, or all faces degenerate) or an
///        option is out of range.
SurfaceAnalysis analyze_surface(const TriangleMesh& mesh, const SurfaceOptions& options);

}  // namespace meshtour
