// The up-axis rule (mesh/up_axis.h). A model standing upright rests on its base: gravity along
// -up puts it on the hull face under it, and of the six axis directions the natural one is the one
// where that rest is firm. Firm means three things together, each measured on the convex hull
// (a table, the floor and the renderer's ground plane only ever touch the hull):
//  * the support polygon (the hull facets facing down within kSupportAngle) is large compared with
//    the model's footprint: a bust's base or four feet, not the top of a head or a curved back;
//  * the centroid projects well inside it (else the model would tip over);
//  * the centroid sits low above it (a lower centre of mass is the firmer rest of two equal bases).
// The rest multiplies these, so a rest that fails any of them scores 0. Two cues that are not
// about resting join it, both measured in the same pass over the triangles:
//  * a flat base: sculptures are cut flat or put on a plinth, scans are open or filled flat where
//    the scanner could not see, figures have soles; the top (a crown, ears, a back) is round. A
//    base flatter than the top by more than the pose's noise adds to the rest: this finds the
//    kitten and the Nefertiti bust firmly, and the figures whose feet give no firm rest;
//  * the plane of bilateral symmetry: up lies in it, so its normal is never up. A truck or a
//    figure rests firmly on its flank; the mirror test rules that out.
// Measured alternatives that did not separate up from the other sides on the shared and fetched
// models, so they are not used: the centroid below mid-height (figures and heads are top-heavy,
// the bunny and teapot bottom-heavy), the cross-section shrinking toward the top (a head over a
// neck grows), and rests on the hull's tilted faces (a head rests on its side more firmly than
// on its neck).
#include "mesh/up_axis.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <numbers>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "core/disjoint_sets.h"
#include "core/error.h"
#include "core/triangle_geometry.h"
#include "mesh/convex_hull.h"
#include "mesh/mesh_edges.h"
#include "mesh/mesh_formats.h"
#include "mesh/vertex_clustering.h"

namespace meshtour {
namespace {

// Hull facets within this angle of straight down carry the model: a scan's flat base is rarely
// exactly perpendicular to the axis, and a hull facet spanning feet tilts by a few degrees.
constexpr double kSupportAngleDeg = 12.0;
// The winner decides when its score is at least kFirmScore and this factor ahead of the runner-up.
// Measured (tests/mesh_up_axis_test.cpp and the fetched models of docs/EVALUATION.md): the models found
// score 0.016-0.82 and most beat the next side by 4x or more (a scorpion on its legs over its
// flank by 1.6x); the Venus head's best side scores 0.0003, the bear's 0. Between 0.005 and 0.01
// lay only guesses: a Max Planck head scan (libigl's tutorial data) on its bald crown, 0.0079
// (its neck, cut small, 0.0009), and Cheburashka on its feet, 0.0052, which +y gives anyway.
constexpr double kConfidentRatio = 1.5;
constexpr double kFirmScore = 0.01;
// Facets up to this far (share of the model's size) above the support plane still touch the floor.
constexpr double kPlaneShare = 0.02;
// A flat end: mesh triangles within kFlatAngle of facing straight out of that end, lying within
// kFlatSlab of the model's size of its extreme plane. Measured at 10-30 degrees and 2-5%: wider
// cones and thicker slabs count a round end (the crown of a head, a back) as flat: a dome's cap
// within 30 degrees projects to a quarter of its disc, within 15 degrees to 7%. A scan's real cut
// (a bust's chest, a filled scan hole, a teapot's foot) keeps most of its area at 15 degrees.
constexpr double kFlatAngleDeg = 15.0;
constexpr double kFlatSlab = 0.02;
// The flat base counts by how much it exceeds the flat top (both as shares of the footprint):
// kFlatWeight times the excess over kFlatNoise. Measured on the shared and first fetched models
// (24, native orientation): the true base leads by 0.13-0.67 where it is clearly flat
// (kitten, bunny, teapot, Nefertiti's chest, soles of figures, open scan bottoms); the largest
// lead of a wrong end is 0.069 (the rocker arm's flank; then a Max Planck head's crown 0.067 and
// a bear's back 0.037), so leads below 0.07 are the pose's noise and count nothing. The weight
// makes a clear flat base (lead 0.2-0.3) worth as much as a firm rest (0.04-0.07).
constexpr double kFlatNoise = 0.07;
constexpr double kFlatWeight = 0.3;
// Mirror symmetry: the share of occupied cells of a kSymmetryGrid^3 grid over the bounding box
// whose mirror image across the plane through the centroid (within one cell) is occupied. A plane
// is the model's plane of bilateral symmetry when at least kSymmetric of the cells match and the
// other two planes match kSymmetryLead less. Measured: models with a clear left-right plane
// (figures, heads, the armadillo, Venus, Nefertiti, a cow, a truck) match 0.92-1.00 across it and
// their other planes less by 0.08 (Venus) to 0.6; the posed animals and the bear lead no plane so
// clearly (0.70-0.87), and are left to the other cues.
constexpr int kSymmetryGrid = 24;
constexpr double kSymmetric = 0.9;
constexpr double kSymmetryLead = 0.08;
// A format's prescribed up (glTF: +y) gives way only to a confident choice scoring at least
// kOverrideScore and kOverrideRatio times the prescribed side: the firm rests and clear flat bases
// of the shared and fetched models score 0.04-0.82, while the weakest confident choices
// (0.01-0.02: the armadillo, Suzanne resting on its face) are exactly the ones a file's own
// convention should outrank.
constexpr double kOverrideScore = 0.03;
constexpr double kOverrideRatio = 4.0;
// Nor does it give way for a model thinner than kOverrideThickness of its size along the shape's
// choice: a flat model (a glTF cut-out character made of layered sprites, a relief) rests firmly
// on its face, which says nothing about which way its picture is up.
constexpr double kOverrideThickness = 0.1;

// The sawn base: when no side rests firmly or is clearly flat, a bust or a statue fragment is
// often still cut flat at the bottom, but its cut is tilted and rough (the Venus head's neck: 4 %
// of its surface, 22 degrees off -z, bumps as tall as its crown's curls), so neither an axis'
// support polygon nor a flat end in a thin slab sees it. Seen on a coarse proxy of the surface
// (mesh/vertex_clustering.h: the scan's roughness averages out in its cells, and a finer scan
// gives the same proxy), the cut is a smooth region bounded by a crease all round. A region
// counts as a cut when it is
//  * bounded by proxy edges where the surface turns by more than a crease angle (kCutCreaseDeg),
//  * at least kCutMinArea of the surface, and flat (|sum of area x normal| / area >= kCutFlatness),
//  * an end of the model: nothing of it lies more than kCutBeyond of its size beyond the
//    region's plane (a flat face in the middle of a side is no base),
//  * within kCutAxisDeg of facing down one of the axes, not across the plane of symmetry,
//  * on a model at least kCutThickness as tall along it as its size: a bust or a fragment stands
//    on its cut taller than it is wide, while a flat back on a thin side is where a mask, a relief
//    or a plaque hangs on a wall (or a mask sits on a face), which says nothing of its up.
// The proxy's grid is centred on the model's box, so its cells turn with the model: anchored at
// the box's corner they shifted by up to a cell under a mirror, and a Max Planck head, a camel's
// head and a column scan (libigl, kTDS) stood on a "cut" in one to three of their six orientations
// and in no other. Where the crease lies on a rough rim depends on how the proxy's cells fall, so the regions are
// taken at each of the kCutCreaseDeg angles and the largest that passes wins (at one angle alone,
// the Venus neck merged with the head in one of six orientations). Measured on proxies of 2,000
// and 8,000 cells (the cut is found at creases of 15-25 degrees in the native orientation): the
// Venus head's neck cut, 4-5 % of the surface, 17-23 degrees off -z, 3 % of the size beyond its
// plane; the Igea head (a 268k-face scan of another marble head) 4-5 %, 18-22 degrees off -y;
// both in all six orientations. The bear, the only shared model the rule is not confident on
// without it, keeps +y: its largest flat region is 2.2 % of its surface and 39 degrees off every
// axis. Only consulted when the rests and flat ends leave the choice open, so it moves no
// confident choice (Nefertiti's flat cap, 13 %, faces up).
constexpr std::size_t kCutProxyCells = 2000;
constexpr double kCutCreaseDeg[] = {15.0, 20.0, 25.0, 30.0};
constexpr double kCutMinArea = 0.03;
constexpr double kCutFlatness = 0.9;
constexpr double kCutBeyond = 0.05;
constexpr double kCutAxisDeg = 30.0;
// Measured: the busts and heads found by their cuts are 0.72 (the Fertility statuette) to 1.0
// (Venus, Igea, a gargoyle, a Celtic skull) as tall along the cut's axis as their size; the
// Lynx mask (a 3D-printed wearable mask, dome-experiments) is 0.45 deep behind its flat brow
// band, which stood it on its back before this bound.
constexpr double kCutThickness = 0.5;

struct FlatCut {
  Axis up;                  // the axis opposite the side the cut faces
  double surface_share = 0.0;
  double tilt_deg = 0.0;    // between the cut's normal and the axis
};

// The largest sawn base of `mesh` (see kCutProxyCells), if any. `outward` is +1 when the
// triangles face out of the model, -1 when they face in (the proxy keeps their facing).
std::optional<FlatCut> flat_cut(const TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& hull, const Eigen::Vector3d& height,
                                int symmetry_normal, double outward) {
  const double model_size = height.maxCoeff();  // `height`: the bounding box's size along each axis
  const TriangleMesh proxy = cluster_surface(mesh, kCutProxyCells, /*centred_grid=*/true).mesh;
  const std::size_t faces = proxy.triangles.size();
  std::vector<Eigen::Vector3d> area_normal(faces);  // area times unit normal
  std::vector<double> area(faces);
  double total = 0.0;
  for (std::size_t f = 0; f < faces; ++f) {
    const auto& t = proxy.triangles[f];
    const Eigen::Vector3d &a = proxy.positions[t[0]], &b = proxy.positions[t[1]], &c = proxy.positions[t[2]];
    area_normal[f] = 0.5 * outward * triangle_cross(a, b, c);
    area[f] = area_normal[f].norm();
    total += area[f];
  }
  // Faces that share an edge: (lower vertex, higher vertex, face), sorted.
  std::vector<std::array<std::uint32_t, 3>> edges;
  edges.reserve(3 * faces);
  for (std::size_t f = 0; f < faces; ++f)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t u = proxy.triangles[f][static_cast<std::size_t>(k)], v = proxy.triangles[f][static_cast<std::size_t>((k + 1) % 3)];
      edges.push_back({std::min(u, v), std::max(u, v), static_cast<std::uint32_t>(f)});
    }
  std::sort(edges.begin(), edges.end());
  std::optional<FlatCut> best;
  for (const double crease_deg : kCutCreaseDeg) {
    // Regions: faces joined across every edge two faces share that turns by less than the crease.
    DisjointSets regions(faces);
    const double cos_crease = std::cos(crease_deg * std::numbers::pi / 180.0);
    for (std::size_t i = 0; i + 1 < edges.size();) {
      std::size_t j = i + 1;
      while (j < edges.size() && edges[j][0] == edges[i][0] && edges[j][1] == edges[i][1]) ++j;
      const std::uint32_t f = edges[i][2], g = edges[i + 1][2];
      if (j == i + 2 && area[f] > 0.0 && area[g] > 0.0 && area_normal[f].dot(area_normal[g]) >= cos_crease * area[f] * area[g])
        regions.join(f, g);
      i = j;
    }
    std::vector<double> region_area(faces, 0.0);
    std::vector<Eigen::Vector3d> region_normal(faces, Eigen::Vector3d::Zero()), region_centre(faces, Eigen::Vector3d::Zero());
    for (std::size_t f = 0; f < faces; ++f) {
      const std::uint32_t r = regions.root(static_cast<std::uint32_t>(f));
      const auto& t = proxy.triangles[f];
      region_area[r] += area[f];
      region_normal[r] += area_normal[f];
      region_centre[r] += area[f] * (proxy.positions[t[0]] + proxy.positions[t[1]] + proxy.positions[t[2]]) / 3.0;
    }
    const double cos_axis = std::cos(kCutAxisDeg * std::numbers::pi / 180.0);
    for (std::size_t r = 0; r < faces; ++r) {
      if (!(region_area[r] >= kCutMinArea * total) || region_normal[r].norm() < kCutFlatness * region_area[r]) continue;
      const Eigen::Vector3d n = region_normal[r].normalized(), centre = region_centre[r] / region_area[r];
      double beyond = -std::numeric_limits<double>::infinity(), lowest = std::numeric_limits<double>::infinity();
      for (const Eigen::Vector3d& p : hull) {
        beyond = std::max(beyond, (p - centre).dot(n));
        lowest = std::min(lowest, (p - centre).dot(n));
      }
      Eigen::Index k = 0;
      n.cwiseAbs().maxCoeff(&k);
      if (beyond > kCutBeyond * model_size || beyond - lowest < kOverrideThickness * model_size || std::abs(n[k]) < cos_axis ||
          k == symmetry_normal || height[k] < kCutThickness * model_size)
        continue;
      const double share = region_area[r] / total;
      if (!best || share > best->surface_share)
        best = FlatCut{Axis{static_cast<int>(k), n[k] > 0.0}, share, std::acos(std::min(1.0, std::abs(n[k]))) * 180.0 / std::numbers::pi};
    }
  }
  return best;
}

// Air under the model, per side: a vessel put down on its mouth, furniture on its legs. A bowl,
// cup or plate rests most firmly upside down (its rim spans the whole footprint, its foot ring a
// small part), and the rests and flat ends cannot tell it from a dome on its base. What tells them
// apart is the air under it: upside down, the vessel's hollow is a pocket closed all round by the
// rim on the floor; under an animal's belly, a table or a car the air runs out sideways, and a
// figure or a bust on its base has none. Measured per side on a grid of columns over the bounding
// box (kPocketGrid across each side): a column's roof is the first surface above the floor, and
// its air is trapped up to the height at which it could not reach the open air around the model
// through columns with higher roofs (the water-filling of a terrain, upside down: a max-min flood
// from outside); above that it is open. A roof seen from behind (an open scan's shell seen from
// inside through its missing bottom) is no air: the open-bottom scan of a statue keeps its hole as
// its base (the flat-base cue above). Both are shares of the bounding box (columns x height).
constexpr int kPocketGrid = 64;
// A vessel on its mouth. Measured (tests/mesh_up_axis_test.cpp's lathe vessels; 72 shared and
// fetched models, all six sides): upside down, a bowl traps 0.45 of its box, a bowl on a recessed
// foot ring 0.46, a cup 0.45, a plate 0.22, a goblet 0.22; right side up, the goblet's hollow foot
// 0.02, the foot ring 0.003; 11 real bowls, mugs, jars, vases and a teapot 0.23-0.54. Of 88 models
// that are no vessels (shared, fetched, 16 real pieces of furniture) the most is a bookcase's
// shelves open to the floor, 0.11, then an upside-down pizza's crust, 0.083 and tables' aprons,
// 0.055; 0.15 or more under a side that traps more than the other end is a vessel upside down.
constexpr double kPocketShare = 0.15;
// A round model (a thrown pot) needs less: its shadow along the axis fills the disc of its box's
// widths across it within kRoundShadow, and those widths agree within kRoundShadow (a square
// fills 4/pi = 1.27 of it, a bookcase lying on its back more). Then kRoundPocketShare under one end,
// more than under the other, is a vessel's mouth: a vase scanned only a little way into its neck
// traps just that (a GGG SfM black vase 0.107 under its mouth, which it rests on more firmly than
// on its narrow foot). Measured on the round sides (fill 0.90-1.08) of 89 fetched models in all six
// orientations: under the end a round model truly stands on, at most 0.019 (a Venetian mask;
// a pizza 0.011, an SfM vase 0.010; the tests' goblet's hollow foot 0.02). No answer but the
// black vase's moved.
constexpr double kRoundShadow = 0.1;
constexpr double kRoundPocketShare = 0.05;
// Furniture on its legs (see choose_up_axis). Measured (the test's table, stool, bench and chair):
// on their legs 0.46-0.94 of their box is open air under them, and the legs span 71-87% of the
// footprint; lying on the top or seat, 0-0.02 (a real desk 0.03). Of the 72 shared and fetched
// models, six sides have 0.4 or more open air under them; the only firm rest among them is a
// hammer standing on its handle (0.71, support 15% of the footprint). The closest firm rests
// below: an upside-down pizza (0.34, support 53%) and a car on its roof (0.33, support 10%).
constexpr double kFlatClearance = 0.1;
constexpr double kLegsClearance = 0.4;
constexpr double kLegsSupport = 0.5;
// A figure lying flat (see choose_up_axis): thickness along its firmest rest between these shares
// of its length, and its arm span at least kFigureSpread of its height. Measured: T-posed human
// models 0.17 thick, spans 0.95-1.0; the A-posed ogre 0.30, 0.97. The lower bound leaves truly
// flat things lying (sprites, plaques, leaves, a pinned butterfly: under a tenth), the upper
// bound figures that are not slabs (a car 0.34 thick is 0.41 as wide as long, and never spread).
constexpr double kFigureThickness[2] = {0.1, 0.35};
constexpr double kFigureSpread = 0.7;

// A hole is an open end of the model when it reaches this close (share of the model's size) to
// the model's extreme in the direction its cap faces. Measured on open scans: the missing
// underside of the GGG SfM vases and jug lies on their extreme (0.000 of their size), open
// busts' chests and necks on theirs; the vessels' unscanned insides end 0.11 (the jug's neck) to
// 0.26 (the black vase's) short of their mouths.
constexpr double kHoleSlab = 0.05;

// The holes of an open mesh, each closed by a cap: a fan from the hole's centre over its edges.
struct Holes {
  // Per hole at an end (kHoleSlab): the cap's vector area (area times its normal, facing out of
  // the model). That end is the model's open base or top.
  std::vector<Eigen::Vector3d> end_caps;
  // The caps of the other holes, as triangles facing out of the model (like `mesh` with
  // `outward`): a vessel's unscanned inside, closed where the scan stopped.
  TriangleMesh inner_caps;
};

// A triangle's boundary edges run around it counter-clockwise seen from outside (`outward` = +1),
// so a cap closing them runs the other way: its vector area is -1/2 the sum of (p_u - o) x
// (p_v - o) over its edges, the same for any o when the loop closes (o: the hole's centre).
Holes find_holes(const TriangleMesh& mesh, double outward, const std::vector<Eigen::Vector3d>& hull, double model_size) {
  const EdgeTally tally = tally_edges(mesh);
  Holes holes;
  for (const std::vector<std::uint32_t>& loop : boundary_loops(mesh, tally)) {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero(), vector_area = Eigen::Vector3d::Zero();
    for (const std::uint32_t e : loop) centre += mesh.positions[tally.boundary[e][0]];
    centre /= static_cast<double>(loop.size());
    for (const std::uint32_t e : loop) {
      const Eigen::Vector3d &p = mesh.positions[tally.boundary[e][0]], &q = mesh.positions[tally.boundary[e][1]];
      vector_area -= 0.5 * outward * triangle_cross(centre, p, q);
    }
    if (!(vector_area.norm() > 0.0)) continue;
    const Eigen::Vector3d n = vector_area.normalized();
    double reach = -std::numeric_limits<double>::infinity(), extreme = reach;
    for (const std::uint32_t e : loop) reach = std::max(reach, mesh.positions[tally.boundary[e][0]].dot(n));
    for (const Eigen::Vector3d& p : hull) extreme = std::max(extreme, p.dot(n));
    if (reach >= extreme - kHoleSlab * model_size) {
      holes.end_caps.push_back(vector_area);
      continue;
    }
    // Triangles (centre, q, p) face the way the cap does when rasterized with `outward`.
    TriangleMesh& caps = holes.inner_caps;
    const auto centre_index = static_cast<std::uint32_t>(caps.positions.size());
    caps.positions.push_back(centre);
    for (const std::uint32_t e : loop) {
      const auto at = static_cast<std::uint32_t>(caps.positions.size());
      caps.positions.push_back(mesh.positions[tally.boundary[e][0]]);
      caps.positions.push_back(mesh.positions[tally.boundary[e][1]]);
      caps.triangles.push_back({centre_index, at + 1, at});
    }
  }
  return holes;
}

struct AirUnder {
  std::array<double, 6> trapped{};  // per side (as UpChoice::rests): air closed in under the model
  std::array<double, 6> open{};     // air under the model that reaches the open air around it
};

// `caps` closes the holes that are no open end (find_holes): seen from under a vessel on its
// mouth, the cap where the scan of its inside stopped is its roof, as its unscanned floor would be.
AirUnder air_under(const TriangleMesh& mesh, const TriangleMesh& caps, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double outward) {
  constexpr int G = kPocketGrid;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Per axis k, per column of the other two coordinates: the lowest surface point (and whether its
  // triangle faces down, out of the solid) and the highest (whether it faces up).
  struct Column {
    double low = kInf, high = -kInf;
    bool low_faces_out = false, high_faces_out = false;
    // The lowest and highest points whatever the order (a tie goes to the side facing out), so
    // the result does not depend on how the triangles were split among threads.
    void put(double height, bool faces_down, bool faces_up) {
      if (height < low || (height == low && faces_down)) low = height, low_faces_out = faces_down;
      if (height > high || (height == high && faces_up)) high = height, high_faces_out = faces_up;
    }
    void merge(const Column& o) {
      if (o.low < low || (o.low == low && o.low_faces_out)) low = o.low, low_faces_out = o.low_faces_out;
      if (o.high > high || (o.high == high && o.high_faces_out)) high = o.high, high_faces_out = o.high_faces_out;
    }
  };
  using Grids = std::array<std::vector<Column>, 3>;
  const Eigen::Vector3d extent = (hi - lo).cwiseMax(1e-300);
  const Eigen::Vector3d to_cells = Eigen::Vector3d::Constant(G).cwiseQuotient(extent);
  const auto rasterize = [&](const TriangleMesh& mesh, std::size_t first, std::size_t last, Grids& columns) {
    for (std::size_t f = first; f < last; ++f) {
      const auto& t = mesh.triangles[f];
      const Eigen::Vector3d &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
      const Eigen::Vector3d n = outward * triangle_cross(a, b, c);
      // Column coordinates of the corners (column centres sit at i + 0.5).
      const Eigen::Vector3d ca = (a - lo).cwiseProduct(to_cells), cb = (b - lo).cwiseProduct(to_cells), cc = (c - lo).cwiseProduct(to_cells);
      const Eigen::Vector3d cmin = ca.cwiseMin(cb).cwiseMin(cc), cmax = ca.cwiseMax(cb).cwiseMax(cc);
      const Eigen::Vector3d pmin = a.cwiseMin(b).cwiseMin(c), pmax = a.cwiseMax(b).cwiseMax(c);
      for (int k = 0; k < 3; ++k) {
        const int u = (k + 1) % 3, v = (k + 2) % 3;  // the column's coordinates
        std::vector<Column>& grid = columns[static_cast<std::size_t>(k)];
        const bool faces_down = n[k] <= 0.0, faces_up = n[k] >= 0.0;
        const int i0 = std::max(0, static_cast<int>(std::ceil(cmin[u] - 0.5))), i1 = std::min(G - 1, static_cast<int>(std::floor(cmax[u] - 0.5)));
        const int j0 = std::max(0, static_cast<int>(std::ceil(cmin[v] - 0.5))), j1 = std::min(G - 1, static_cast<int>(std::floor(cmax[v] - 0.5)));
        const double det = (cb[u] - ca[u]) * (cc[v] - ca[v]) - (cc[u] - ca[u]) * (cb[v] - ca[v]);
        bool any = false;
        if (i0 <= i1 && j0 <= j1 && std::abs(det) > 1e-12)
          for (int i = i0; i <= i1; ++i)
            for (int j = j0; j <= j1; ++j) {  // the triangle's exact height at the centres in its shadow
              const double pu = i + 0.5 - ca[u], pv = j + 0.5 - ca[v];
              const double s = (pu * (cc[v] - ca[v]) - pv * (cc[u] - ca[u])) / det, r = ((cb[u] - ca[u]) * pv - (cb[v] - ca[v]) * pu) / det;
              if (s < -1e-9 || r < -1e-9 || s + r > 1.0 + 1e-9) continue;
              grid[static_cast<std::size_t>(i * G + j)].put(a[k] + s * (b[k] - a[k]) + r * (c[k] - a[k]), faces_down, faces_up);
              any = true;
            }
        if (!any) {  // smaller than a column (a scan's triangle): its centre's column, its lowest and highest point
          const int i = std::clamp(static_cast<int>((ca[u] + cb[u] + cc[u]) / 3.0), 0, G - 1);
          const int j = std::clamp(static_cast<int>((ca[v] + cb[v] + cc[v]) / 3.0), 0, G - 1);
          Column& col = grid[static_cast<std::size_t>(i * G + j)];
          col.put(pmin[k], faces_down, faces_up);
          col.put(pmax[k], faces_down, faces_up);
        }
      }
    }
  };
  const auto empty_grids = [] {
    Grids g;
    for (auto& c : g) c.assign(static_cast<std::size_t>(G * G), Column{});
    return g;
  };
  const auto merge = [](Grids into, const Grids& from) {
    for (std::size_t k = 0; k < 3; ++k)
      for (std::size_t q = 0; q < into[k].size(); ++q) into[k][q].merge(from[k][q]);
    return into;
  };
  // Chunks of triangles in parallel, each into its own grids, merged (min and max: any order).
  Grids columns = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, mesh.triangles.size(), 1 << 16), empty_grids(),
      [&](const tbb::blocked_range<std::size_t>& range, Grids grids) {
        rasterize(mesh, range.begin(), range.end(), grids);
        return grids;
      },
      merge);
  rasterize(caps, 0, caps.triangles.size(), columns);

  AirUnder share;
  std::vector<double> roof(static_cast<std::size_t>(G * G)), escape(static_cast<std::size_t>(G * G));
  for (int side = 0; side < 6; ++side) {  // side 2k: up +k, resting on the -k end; 2k + 1: up -k
    const int k = side / 2;
    const bool up_negative = side % 2 == 1;
    for (std::size_t q = 0; q < roof.size(); ++q) {
      const Column& c = columns[static_cast<std::size_t>(k)][q];
      if (!up_negative)
        roof[q] = c.low == kInf ? kInf : c.low_faces_out ? c.low - lo[k] : 0.0;
      else
        roof[q] = c.high == -kInf ? kInf : c.high_faces_out ? hi[k] - c.high : 0.0;
    }
    // Max-min flood from the open air: escape[q] is the highest level up to which the air in
    // column q reaches a column with no roof (or the grid's edge) under roofs at least as high.
    std::vector<std::pair<double, int>> heap;
    std::fill(escape.begin(), escape.end(), -1.0);
    for (int i = 0; i < G; ++i)
      for (int j = 0; j < G; ++j) {
        const int q = i * G + j;
        if (roof[static_cast<std::size_t>(q)] == kInf || i == 0 || j == 0 || i == G - 1 || j == G - 1) {
          escape[static_cast<std::size_t>(q)] = roof[static_cast<std::size_t>(q)];
          heap.emplace_back(roof[static_cast<std::size_t>(q)], q);
        }
      }
    std::make_heap(heap.begin(), heap.end());
    while (!heap.empty()) {
      std::pop_heap(heap.begin(), heap.end());
      const auto [level, q] = heap.back();
      heap.pop_back();
      if (level < escape[static_cast<std::size_t>(q)]) continue;  // a stale entry
      const int i = q / G, j = q % G;
      const int next[4][2] = {{i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}};
      for (const auto& [ni, nj] : next) {
        if (ni < 0 || nj < 0 || ni >= G || nj >= G) continue;
        const auto nq = static_cast<std::size_t>(ni * G + nj);
        const double reach = std::min(roof[nq], level);
        if (reach > escape[nq]) {
          escape[nq] = reach;
          heap.emplace_back(reach, static_cast<int>(nq));
          std::push_heap(heap.begin(), heap.end());
        }
      }
    }
    double trapped = 0.0, open = 0.0;
    for (std::size_t q = 0; q < roof.size(); ++q)
      if (roof[q] != kInf) {
        trapped += roof[q] - std::max(0.0, escape[q]);
        open += std::max(0.0, std::min(roof[q], escape[q]));
      }
    // Shares of the bounding box (columns x height), the same box for both ends of an axis.
    share.trapped[static_cast<std::size_t>(side)] = trapped / (static_cast<double>(G) * G * extent[k]);
    share.open[static_cast<std::size_t>(side)] = open / (static_cast<double>(G) * G * extent[k]);
  }
  return share;
}

double polygon_area(const std::vector<Eigen::Vector2d>& p) {
  double a = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Eigen::Vector2d& q = p[i];
    const Eigen::Vector2d& r = p[(i + 1) % p.size()];
    a += q.x() * r.y() - q.y() * r.x();
  }
  return 0.5 * std::abs(a);
}

// Signed distance of `x` to the edges of the counter-clockwise convex polygon `p`: > 0 inside.
double inside_distance(const std::vector<Eigen::Vector2d>& p, const Eigen::Vector2d& x) {
  if (p.size() < 3) return -std::numeric_limits<double>::infinity();
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Eigen::Vector2d e = p[(i + 1) % p.size()] - p[i];
    const Eigen::Vector2d inward(-e.y(), e.x());
    d = std::min(d, inward.dot(x - p[i]) / e.norm());
  }
  return d;
}

}  // namespace

UpChoice choose_up_axis(const TriangleMesh& mesh) {
  const std::vector<Eigen::Vector3d> hull = convex_hull_vertices(mesh);
  const std::vector<HullTriangle> facets = convex_hull_triangles(hull);
  const double cos_support = std::cos(kSupportAngleDeg * std::numbers::pi / 180.0);
  Eigen::Vector3d lo = hull.front(), hi = lo;  // the bounding box (the hull's is the model's)
  for (const Eigen::Vector3d& p : hull) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double model_size = (hi - lo).maxCoeff();  // for the plane tolerances
  const Eigen::Vector3d extent = (hi - lo).cwiseMax(1e-12 * std::max(1.0, model_size));
  const Eigen::Vector3d middle = 0.5 * (lo + hi);

  // One pass over the triangles gathers everything the cues need (linear in faces, no topology):
  //  * the surface centroid (area-weighted): the centre of mass of a shell, and close to the
  //    solid's for a scan; it needs no closed surface;
  //  * flat ends: per side, the projected area of the triangles at that end that face out of it
  //    (a cut, a plinth, soles, a filled scan hole). A bust's chest or a statue's plinth is flat
  //    and at the bottom; the top of a head, ears or a back are round;
  //  * the vector area and signed volume (open scans and inward normals, below);
  //  * the cells the surface occupies, for the mirror symmetry test.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double area = 0.0;
  std::array<double, 6> flat{};  // flat[2k]: facing +k at the +k end; flat[2k + 1]: facing -k at the -k end
  const double cos_flat = std::cos(kFlatAngleDeg * std::numbers::pi / 180.0);
  const double slab = kFlatSlab * model_size;
  double volume6 = 0.0;                                   // six times the signed volume (> 0: normals point out)
  constexpr int G = kSymmetryGrid;
  std::vector<unsigned char> occupied(static_cast<std::size_t>(G * G * G), 0);
  const Eigen::Vector3d cells_per_unit = Eigen::Vector3d::Constant(G).cwiseQuotient(extent);
  const auto cell = [&](double x, int k) { return std::clamp(static_cast<int>((x - lo[k]) * cells_per_unit[k]), 0, G - 1); };
  const auto cell_index = [](int x, int y, int z) { return static_cast<std::size_t>((x * G + y) * G + z); };
  const auto mark = [&](const Eigen::Vector3d& p) { occupied[cell_index(cell(p.x(), 0), cell(p.y(), 1), cell(p.z(), 2))] = 1; };
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    const Eigen::Vector3d cross = triangle_cross(a, b, c);
    const double w = triangle_area(a, b, c);
    if (!(w > 0.0)) continue;
    const Eigen::Vector3d m = (a + b + c) / 3.0;
    centroid += w * m;
    area += w;
    volume6 += (a - middle).dot((b - middle).cross(c - middle));
    // The surface's cells: the centroid of a triangle smaller than a cell (a scan's), else a
    // barycentric grid of points no further apart than a cell (a CAD part's long triangles: their
    // centroids alone sit at a third of each quad's diagonal and look asymmetric).
    const Eigen::Vector3d tri_lo = a.cwiseMin(b).cwiseMin(c), tri_hi = a.cwiseMax(b).cwiseMax(c);
    const double span = (tri_hi - tri_lo).cwiseProduct(cells_per_unit).maxCoeff();
    if (span <= 1.0) {
      mark(m);
    } else {
      const int steps = static_cast<int>(std::ceil(std::min(span, 4.0 * G)));
      for (int i = 0; i <= steps; ++i)
        for (int j = 0; i + j <= steps; ++j) mark(a + (b - a) * (static_cast<double>(i) / steps) + (c - a) * (static_cast<double>(j) / steps));
    }
    const Eigen::Vector3d n = cross / (2.0 * w);
    for (int k = 0; k < 3; ++k) {
      if (n[k] >= cos_flat && tri_lo[k] >= hi[k] - slab) flat[static_cast<std::size_t>(2 * k)] += w * n[k];
      if (-n[k] >= cos_flat && tri_hi[k] <= lo[k] + slab) flat[static_cast<std::size_t>(2 * k + 1)] -= w * n[k];
    }
  }
  if (!(area > 0.0)) throw InputError("--up auto: the mesh has no area, so it has no side to rest on");
  centroid /= area;
  // A mesh whose normals point in (signed volume < 0) has the ends' roles swapped.
  const double outward = volume6 < 0.0 ? -1.0 : 1.0;  // the triangles' facing: out of the model, or into it
  if (volume6 < 0.0)
    for (std::size_t k = 0; k < 3; ++k) std::swap(flat[2 * k], flat[2 * k + 1]);
  // An open mesh: a scan's hole at one end of the model is usually its base, which the scanner
  // could not see (a bust's open chest or neck, a statue's or a vase's underside), so the cap that
  // would close it counts as flat surface at the end it faces, where a flat triangle would: facing
  // within kFlatAngle of the axis. (Counting its shadow on every axis stood a lion's head scan,
  // libigl's lion.off, on its open throat, 27 degrees off its back and nowhere near its up, in all
  // six orientations; of 89 fetched models no other answer moved.) A hole that does not reach an end
  // (kHoleSlab) says nothing about the base: a vessel's unscanned inside ends in one deep in its
  // neck or on its inner floor, facing up, and counted it would stand the vessel on its mouth.
  // Closed meshes (all shared ones) have no holes. Measured: the open head scan (libigl face.obj)
  // gets a base lead of 0.67 from its open neck.
  const Holes holes = find_holes(mesh, outward, hull, model_size);
  for (const Eigen::Vector3d& cap : holes.end_caps)
    for (std::size_t k = 0; k < 3; ++k)
      if (std::abs(cap[static_cast<Eigen::Index>(k)]) >= cos_flat * cap.norm())
        flat[cap[static_cast<Eigen::Index>(k)] > 0.0 ? 2 * k : 2 * k + 1] += std::abs(cap[static_cast<Eigen::Index>(k)]);

  UpChoice choice;
  for (int j = 0; j < 3; ++j) {  // the plane through the centroid normal to axis j
    std::size_t cells = 0, mirrored = 0;
    for (int x = 0; x < G; ++x)
      for (int y = 0; y < G; ++y)
        for (int z = 0; z < G; ++z) {
          if (!occupied[cell_index(x, y, z)]) continue;
          ++cells;
          std::array<int, 3> q{x, y, z};
          const auto jj = static_cast<std::size_t>(j);
          q[jj] = cell(2.0 * centroid[j] - (lo[j] + (q[jj] + 0.5) / G * extent[j]), j);
          bool found = false;
          for (int dx = -1; dx <= 1 && !found; ++dx)
            for (int dy = -1; dy <= 1 && !found; ++dy)
              for (int dz = -1; dz <= 1 && !found; ++dz) {
                const int u = q[0] + dx, v = q[1] + dy, s = q[2] + dz;
                found = u >= 0 && v >= 0 && s >= 0 && u < G && v < G && s < G && occupied[cell_index(u, v, s)];
              }
          mirrored += found ? 1 : 0;
        }
    choice.symmetry[static_cast<std::size_t>(j)] = cells ? static_cast<double>(mirrored) / static_cast<double>(cells) : 0.0;
  }
  {
    std::array<int, 3> by{0, 1, 2};
    const auto sym = [&](int a) { return choice.symmetry[static_cast<std::size_t>(a)]; };
    std::sort(by.begin(), by.end(), [&](int a, int b) { return sym(a) > sym(b); });
    if (sym(by[0]) >= kSymmetric && sym(by[0]) - sym(by[1]) >= kSymmetryLead) choice.symmetry_normal = by[0];
  }

  // The rest with gravity along `down`: on the hull facets within kSupportAngle of facing `down`
  // that touch the support plane.
  const auto rest_on = [&](const Eigen::Vector3d& down, UpRest& rest) {
    const Eigen::Vector3d e1 = down.unitOrthogonal(), e2 = down.cross(e1);
    const auto flat2 = [&](const Eigen::Vector3d& p) { return Eigen::Vector2d(p.dot(e1), p.dot(e2)); };
    std::vector<Eigen::Vector2d> all, support;
    double bottom = std::numeric_limits<double>::infinity(), top = -bottom;
    for (const Eigen::Vector3d& p : hull) {
      all.push_back(flat2(p));
      bottom = std::min(bottom, -p.dot(down));
      top = std::max(top, -p.dot(down));
    }
    const double tolerance = kPlaneShare * model_size;
    for (const HullTriangle& t : facets)
      if (t.normal.dot(down) >= cos_support &&
          std::all_of(t.corner.begin(), t.corner.end(), [&](const Eigen::Vector3d& c) { return -c.dot(down) - bottom <= tolerance; }))
        for (const Eigen::Vector3d& c : t.corner) support.push_back(flat2(c));
    const std::vector<Eigen::Vector2d> footprint = convex_polygon(std::move(all));
    const std::vector<Eigen::Vector2d> base = convex_polygon(std::move(support));
    const double footprint_area = polygon_area(footprint);
    if (!(footprint_area > 0.0) || !(top > bottom)) return;
    rest.footprint = footprint_area;
    if (base.size() < 3) return;
    rest.support_area = polygon_area(base) / footprint_area;
    rest.margin = inside_distance(base, flat2(centroid)) / std::sqrt(footprint_area / std::numbers::pi);
    rest.centroid_height = (-centroid.dot(down) - bottom) / (top - bottom);
    rest.rest = rest.margin > 0.0 ? rest.support_area * rest.margin * (1.0 - rest.centroid_height) : 0.0;
  };

  const AirUnder air = air_under(mesh, holes.inner_caps, lo, hi, outward);
  for (int k = 0; k < 6; ++k) {
    UpRest& rest = choice.rests[static_cast<std::size_t>(k)];
    rest.up = Axis{k / 2, k % 2 == 1};
    rest_on(-rest.up.vector(), rest);
    rest.trapped_air = air.trapped[static_cast<std::size_t>(k)];
    rest.clearance = air.open[static_cast<std::size_t>(k)];
  }
  for (int k = 0; k < 6; ++k) {
    UpRest& rest = choice.rests[static_cast<std::size_t>(k)];
    const double footprint = rest.footprint;
    // With `up` up, the base is the end facing -up (flat[k ^ 1]) and the top the end facing up.
    if (footprint > 0.0) {
      rest.flat_base = flat[static_cast<std::size_t>(k ^ 1)] / footprint;
      rest.flat_top = flat[static_cast<std::size_t>(k)] / footprint;
    }
    const double lead = rest.flat_base - rest.flat_top;
    rest.score = rest.rest + kFlatWeight * std::max(0.0, lead - kFlatNoise);
    if (rest.up.index == choice.symmetry_normal) rest.score = 0.0;
  }

  // Ties (a cube) go to the earlier rest of this order (+y first: the glTF and most scanners' up).
  std::array<std::size_t, 6> order{2, 4, 0, 3, 5, 1};
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return choice.rests[a].score > choice.rests[b].score;
  });
  const UpRest& best = choice.rests[order[0]];
  const UpRest& second = choice.rests[order[1]];
  choice.margin = second.score > 0.0 ? best.score / second.score : std::numeric_limits<double>::infinity();
  // Only a firm rest or a clearly flat base that beats the others overrides the file's convention
  // (+y): a guess would turn the model on its side.
  choice.confident = best.score >= kFirmScore && best.score >= kConfidentRatio * second.score;
  choice.up = choice.confident ? best.up : Axis{1, false};
  // A vessel on its mouth: a side it rests on traps air under it, more than the other end does (a
  // goblet's hollow foot, a foot ring), so it stands the other way up, mouth up. That side is the
  // firmest rest (a bowl's rim spans the footprint), or the runner-up to its own opposite (a vase
  // whose foot is as wide as its mouth: then the foot was right, and is now sure). Checked
  // whether or not the rest was confident: a cup's rim and its foot are both firm rests. A round
  // model needs less air under it (kRoundPocketShare).
  // Round about an axis: its shadow along it fills the disc of its box's widths across it.
  const auto round_about = [&](const UpRest& r) {
    const int i = (r.up.index + 1) % 3, j = (r.up.index + 2) % 3;
    const double disc = std::numbers::pi / 4.0 * extent[i] * extent[j];
    return std::abs(r.footprint / disc - 1.0) <= kRoundShadow &&
           std::min(extent[i], extent[j]) >= (1.0 - kRoundShadow) * std::max(extent[i], extent[j]);
  };
  const auto mouth_down = [&](std::size_t k) {
    const UpRest& r = choice.rests[k];
    const double pocket = round_about(r) ? kRoundPocketShare : kPocketShare;
    return r.score > 0.0 && r.trapped_air >= pocket && choice.rests[k ^ 1].trapped_air < r.trapped_air;
  };
  const UpRest* mouth = mouth_down(order[0])                                 ? &choice.rests[order[0]]
                        : mouth_down(order[1]) && order[0] == (order[1] ^ 1) ? &choice.rests[order[1]]
                                                                             : nullptr;
  const UpRest* mouth_up = mouth ? &choice.rests[static_cast<std::size_t>(mouth - choice.rests.data()) ^ 1] : nullptr;
  const bool upside_down = mouth != nullptr;
  if (upside_down) {
    choice.up = mouth_up->up;
    choice.confident = true;
    choice.upside_down_air = mouth->trapped_air;
  }
  // Furniture: a table, stool, bench or chair rests more firmly on its top or seat (flat, heavy,
  // the whole footprint) than on its legs. Standing on its legs, most of its box under it is open
  // air (kLegsClearance) and the legs span most of its footprint (kLegsSupport); lying on its top,
  // none is (kFlatClearance). That is never so of a statue, animal, vessel or tool (measured below).
  // A chair on its legs may also lead its back by too little to be confident: that is no doubt.
  const auto on_legs = [](const UpRest& r) { return r.score >= kFirmScore && r.support_area >= kLegsSupport && r.clearance >= kLegsClearance; };
  const UpRest* legs = nullptr;
  if (!upside_down && best.score > 0.0 && (best.clearance <= kFlatClearance || on_legs(best)))
    for (const std::size_t k : order)
      if (on_legs(choice.rests[k])) {
        legs = &choice.rests[k];
        break;
      }
  if (legs == &best && choice.confident) legs = nullptr;  // nothing to add to a confident rest
  if (legs) {
    choice.up = legs->up;
    choice.confident = true;
  }
  // A figure with its limbs spread (a T- or A-pose) is a slab as wide as it is tall, and rests far
  // more firmly on its front or back than on its feet. It is told from things that lie flat by
  // its mirror plane: the plane's normal is a wide axis (the arms), and the third axis, in the
  // plane and as long (head to feet), has a firm rest at one end (the feet). Wide soles can make
  // the feet the firmest rest, but not clearly: then the figure lies on the runner-up, and the
  // feet are sure all the same (a T-posed man scan: feet 0.013, back 0.012).
  const Eigen::Vector3d relative = extent / extent.maxCoeff();
  const auto thin_in_mirror_plane = [&](const UpRest& r) {
    const int other = 3 - r.up.index - choice.symmetry_normal;
    return r.up.index != choice.symmetry_normal && relative[r.up.index] <= relative[other];
  };
  const UpRest* lying = nullptr;
  if (!upside_down && !legs && choice.symmetry_normal >= 0)
    lying = thin_in_mirror_plane(best) ? &best : thin_in_mirror_plane(second) ? &second : nullptr;
  const UpRest* feet = nullptr;
  if (lying && lying->score >= kFirmScore && relative[lying->up.index] >= kFigureThickness[0] &&
      relative[lying->up.index] <= kFigureThickness[1]) {
    const int across = choice.symmetry_normal, along = 3 - lying->up.index - across;
    const UpRest& a = choice.rests[static_cast<std::size_t>(2 * along)];
    const UpRest& b = choice.rests[static_cast<std::size_t>(2 * along + 1)];
    const UpRest& stand = a.score >= b.score ? a : b;
    if (relative[across] >= kFigureSpread * relative[along] && stand.score >= kFirmScore) feet = &stand;
  }
  if (feet) {
    choice.up = feet->up;
    choice.confident = true;
    choice.lying_figure = true;
  }
  std::optional<FlatCut> cut;
  // The sawn base is for models that rest on no side (a head on a slanted neck cut). Where two
  // sides are firm rests, neither clearly ahead, it may break their tie (a vase's foot, larger
  // than its mouth's rim), but only where the cut's end is clearly the flatter (kConfidentRatio):
  // between ends alike (a column's base and capital) it would toss a coin. A flat region elsewhere
  // says nothing (an armchair's back, a bookcase's): +y stays, not confident.
  if (!choice.confident) {
    cut = flat_cut(mesh, hull, extent, choice.symmetry_normal, outward);
    if (cut && best.score >= kFirmScore) {
      const UpRest& on_cut = choice.rest(cut->up);  // standing on the cut
      if ((cut->up != best.up && cut->up != second.up) || on_cut.flat_base < kConfidentRatio * on_cut.flat_top) cut.reset();
    }
  }
  if (cut) {
    choice.confident = true;
    choice.up = cut->up;
    choice.cut_share = cut->surface_share;
  }
  const auto side = [](const Axis& up) { return Axis{up.index, !up.negative}.name(); };
  const std::string symmetry =
      choice.symmetry_normal >= 0 ? std::string(", mirror-symmetric across ") + "xyz"[choice.symmetry_normal] : std::string();
  char text[400];
  if (legs)
    std::snprintf(text, sizeof text,
                  "stands on its legs, its %s side (score %.3g, support %.0f%% of the footprint, %.0f%% of its box open air "
                  "under it): it rests more firmly on its flat %s side (score %.3g), as a table, stool or chair does on its "
                  "top or seat%s",
                  side(legs->up).c_str(), legs->score, 100.0 * legs->support_area, 100.0 * legs->clearance, side(best.up).c_str(),
                  best.score, symmetry.c_str());
  else if (feet)
    std::snprintf(text, sizeof text,
                  "stands on its feet, its %s side (score %.3g): it rests %s firmly on its %s side (score %.3g), but "
                  "there it lies flat (%.0f%% as thick as long) with limbs spread as wide as it is tall (%.0f%%) "
                  "across its mirror plane, a figure in a T- or A-pose%s",
                  side(feet->up).c_str(), feet->score, lying->score > feet->score ? "more" : "almost as", side(lying->up).c_str(),
                  lying->score, 100.0 * relative[lying->up.index],
                  100.0 * relative[choice.symmetry_normal] / relative[3 - lying->up.index - choice.symmetry_normal],
                  symmetry.c_str());
  else if (upside_down)
    std::snprintf(text, sizeof text,
                  "stands mouth up: resting on its %s side (score %.3g; the other way up %.3g) it would trap air under it "
                  "(%.0f%% of its box, %.0f%% the other way up), as a bowl, cup or plate does upside down; a bell or a "
                  "helmet stands on its mouth: give --up %s for one%s",
                  side(mouth->up).c_str(), mouth->score, mouth_up->score, 100.0 * mouth->trapped_air, 100.0 * mouth_up->trapped_air,
                  mouth->up.name().c_str(), symmetry.c_str());
  else if (cut)
    std::snprintf(text, sizeof text,
                  "stands on a flat cut on its %s side (%.1f%% of the surface, %.0f degrees off the axis: a bust's or a "
                  "fragment's sawn base), where no side rests firmly (best %s %.3g, next %s %.3g)%s",
                  side(cut->up).c_str(), 100.0 * cut->surface_share, cut->tilt_deg, best.up.name().c_str(), best.score,
                  second.up.name().c_str(), second.score, symmetry.c_str());
  else if (choice.confident)
    std::snprintf(text, sizeof text,
                  "rests on its %s side: support %.0f%% of the footprint, centroid %.0f%% of the radius inside it, "
                  "%.0f%% of the height above it, flat base %.0f%% (top %.0f%%)%s (score %.3g, next %s %.3g)",
                  side(best.up).c_str(), 100.0 * best.support_area, 100.0 * best.margin, 100.0 * best.centroid_height,
                  100.0 * best.flat_base, 100.0 * best.flat_top, symmetry.c_str(), best.score, second.up.name().c_str(),
                  second.score);
  else
    std::snprintf(text, sizeof text,
                  "no side is clearly the base (best %s %.3g, next %s %.3g; firm is %.3g and %.1fx the next)%s; "
                  "keeping +y, the usual convention",
                  best.up.name().c_str(), best.score, second.up.name().c_str(), second.score, kFirmScore, kConfidentRatio,
                  symmetry.c_str());
  choice.reason = text;
  return choice;
}

std::optional<Axis> format_up_axis(const std::filesystem::path& file) {
  const mesh_formats::MeshFormat* format = mesh_formats::find(file.extension().string());
  return format ? format->up : std::nullopt;
}

bool up_by_shape_by_default(const std::filesystem::path& file) {
  const mesh_formats::MeshFormat* format = mesh_formats::find(file.extension().string());
  return format && format->up_by_shape;
}

UpChoice choose_up_axis(const TriangleMesh& mesh, const std::filesystem::path& file) {
  UpChoice choice = choose_up_axis(mesh);
  const std::optional<Axis> prescribed = format_up_axis(file);
  if (!prescribed) return choice;
  const double shape = choice.confident ? choice.rest(choice.up).score : 0.0;
  const double format = choice.rest(*prescribed).score;
  const std::string name = file.filename().string();
  const Eigen::Vector3d extent = mesh.bounds().extent();
  const bool thick = extent[choice.up.index] >= kOverrideThickness * extent.maxCoeff();
  if (choice.confident && choice.up != *prescribed && thick && shape >= kOverrideScore && shape >= kOverrideRatio * format) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "%s is glTF, whose up is %s by the specification, but its shape clearly says %s (score %.3g, %s %.3g): "
                  "using %s; give --up %s to keep the file's up",
                  name.c_str(), prescribed->name().c_str(), choice.up.name().c_str(), shape, prescribed->name().c_str(), format,
                  choice.up.name().c_str(), prescribed->name().c_str());
    choice.warning = text;
    return choice;
  }
  if (choice.confident && choice.up == *prescribed)
    choice.reason = "glTF is " + prescribed->name() + " up by the specification, and the shape agrees: " + choice.reason;
  else
    choice.reason = "glTF is " + prescribed->name() + " up by the specification (the shape alone: " + choice.up.name() +
                    (choice.confident ? "" : ", not confident") + "; " + choice.reason + ")";
  choice.up = *prescribed;
  choice.confident = true;
  return choice;
}

bool is_auto_up(std::string_view text) {
  return text.size() == 4 && std::equal(text.begin(), text.end(), "auto", [](char a, char b) {
           return std::tolower(static_cast<unsigned char>(a)) == b;
         });
}

}  // namespace meshtour
