#pragma once
// `--up auto`: which coordinate axis (±x, ±y, ±z) is the model's up, judged by its shape. Each of
// the six sides is scored as the model's base (mesh/up_axis.cpp says how and why):
//  * the rest: put down on that side, how firmly the model would stand (support polygon of the
//    convex hull, the centroid's margin inside it, the centroid's height);
//  * a flat base: how much flat surface faces down at that end (a bust's cut, a plinth, soles, an
//    open scan's missing bottom) beyond what faces up at the other end (a crown is round);
//  * mirror symmetry: an axis normal to the model's clear plane of bilateral symmetry is never up.
//  * a sawn base, only where these leave the choice open: a flat region bounded by a crease, at
//    one end, on a coarse proxy of the surface (a marble head's slanted, rough neck cut).
// The best side wins when it is firm and 1.5x the next, else the sawn base, else +y, said as not
// confident. Three kinds of object rest most firmly the wrong way, and the air under the model
// (on a grid of columns per side) or its proportions turn them over:
//  * a vessel on its mouth (bowl, cup, plate, goblet): the air under it is closed in by the rim,
//    so it stands mouth up (a bell or a helmet, which stand on their mouths, would be turned too);
//  * furniture on its top or seat (table, stool, bench, chair): standing on its legs, most of its
//    box is open air under it, so it stands on its legs;
//  * a figure with its limbs spread (a T- or A-pose) on its back or front: a slab as wide as it
//    is tall with a mirror plane across its width, so it stands on its feet.
// glTF files are +y by their specification, which only a strong, clearly different choice
// overrides (with a warning). Behind `--up auto` (issue 15), and the default for mesh files since
// issue 37 (up_by_shape_by_default; docs/EVALUATION.md#the-default-up-axis).
// Measured (tests/mesh_up_axis_test.cpp prints every side's score): on the shared meshes it finds
// the up of the horse, kitten, bunny and armadillo in all six orientations by their rests and flat
// bases, and of the Venus head by its sawn neck (no side rests on it: tilted 17 degrees, as rough
// as the crown); the bear (upright on one hind leg) gives no side a clear lead and has no cut, so
// it keeps +y, not confident: right only by convention. The rocker arm (no natural up) lies on
// its widest flank. On fetched models (docs/EVALUATION.md lists them and the counts): it is confidently
// wrong on two that rest on their faces and are neither vessels, furniture nor spread figures,
// Blender's Suzanne (a head without a neck) and meshJND's open face mask (on its open back; a flat
// back found as a sawn cut no longer stands a mask on it, see kCutThickness); the
// A-posed ogre and three T-posed humans stand on their feet since the figure cue. The procedural
// vessels, furniture and T-posed figure of the tests are found in all six orientations.
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "core/axis.h"
#include "mesh/mesh.h"

namespace meshtour {

/// How the model rests when `up` points up (gravity along -up), measured on its convex hull.
struct UpRest {
  Axis up;
  double support_area = 0.0;  ///< area of the support polygon / area of the model's footprint
  double margin = 0.0;        ///< distance of the centroid's projection inside the support polygon's edge / footprint radius (< 0: it tips over)
  double centroid_height = 0.0;  ///< height of the surface centroid above the rest plane / the model's height along up
  double rest = 0.0;          ///< 0 when the rest is not stable; larger is firmer (see up_axis.cpp)
  double footprint = 0.0;     ///< area of the hull's shadow along up (the unit of the flat areas)
  double flat_base = 0.0;     ///< area of the flat surface facing down at the bottom / footprint
  double flat_top = 0.0;      ///< the same facing up at the top
  double score = 0.0;         ///< rest and flat base combined (see up_axis.cpp); 0 across a symmetry plane
  double trapped_air = 0.0;   ///< air enclosed under the model resting so (a vessel on its mouth), share of its bounding box
  double clearance = 0.0;     ///< air under the model resting so that reaches the open air around it (under a table, between legs), share of its bounding box
};

/// The chosen up axis, why, and all six rests (in the order +x, -x, +y, -y, +z, -z).
struct UpChoice {
  Axis up;
  std::string reason;  ///< one line for the user, e.g. "rests on its -y side: support 47% of the footprint, ..."
  bool confident = false;  ///< some side rests firmly and clearly (see up_axis.cpp) ahead of the others; else up is +y
  std::array<UpRest, 6> rests;
  /// The rest with `up` up.
  const UpRest& rest(const Axis& up) const { return rests[static_cast<std::size_t>(2 * up.index + (up.negative ? 1 : 0))]; }
  std::array<double, 3> symmetry{};  ///< share of the surface mirrored across the plane through the centroid normal to x, y, z
  int symmetry_normal = -1;          ///< the axis normal to the clear plane of symmetry (never up), or -1
  double margin = 0.0;               ///< best score / second best score
  /// Share of the surface of the flat cut (a bust's sawn base) that chose `up` where the rests and
  /// flat ends did not; 0 when they decided or nothing did.
  double cut_share = 0.0;
  /// The air the firmest rest would trap under the model, when that turned it over (a bowl, cup
  /// or plate stands mouth up); else 0.
  double upside_down_air = 0.0;
  /// True when a figure with spread limbs lay on its front or back (the firmest rest, or almost
  /// as firm as its feet), and it was stood on its feet instead.
  bool lying_figure = false;
  /// Not empty when the shape overrode the up its file format prescribes (glTF: +y), saying so.
  std::string warning;
};

/// The up axis by shape (+y when no side rests firmly and clearly ahead of the others). Deterministic;
/// linear in the triangles: 30 ms at 70k faces, 3.0 s at 17.8M (bench/framing_bench BM_UpAxis).
/// \throw InputError if the mesh has no area (nothing to rest on).
UpChoice choose_up_axis(const TriangleMesh& mesh);

/// The up axis a file format prescribes: +y for glTF (.gltf, .glb; the glTF 2.0 specification
/// makes +Y up), nothing for formats without a convention (OBJ, PLY, OFF, STL).
std::optional<Axis> format_up_axis(const std::filesystem::path& file);

/// choose_up_axis() for a model loaded from `file`. When the format prescribes an up (glTF: +y),
/// that is the answer unless the shape's choice is confident, disagrees, and is strong: a score of
/// at least 0.03 (a firm rest or a clearly flat base) and 4x the prescribed side's, on a model at
/// least a tenth as thick along it as its size (a flat model rests on its face whatever its up).
/// Then the shape wins and `warning` says that it overrode the format's up.
/// \throw InputError if the mesh has no area.
UpChoice choose_up_axis(const TriangleMesh& mesh, const std::filesystem::path& file);

/// Whether a model read from `file` is stood up by this rule when no --up is given (the format's
/// row in mesh/mesh_formats.cpp: every format meshtour reads); false for an unknown format.
bool up_by_shape_by_default(const std::filesystem::path& file);

/// Whether an --up value asks for this rule ("auto", any case).
bool is_auto_up(std::string_view text);

}  // namespace meshtour
