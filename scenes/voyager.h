#pragma once
// Smithsonian Voyager scene documents (".svx.json", the SVX schema of
// github.com/smithsonian/dpo-voyager, source/client/schema/json): what a museum's own viewer
// knows about a model that its mesh file does not say. Read here, at the edge, into plain values:
//  * the model's pose: the transforms of the nodes above it, then the model's own rotation and
//    translation (its "neutral pose") and its units scaled to the scene's (setups[].units), as
//    Voyager's CVModel2 applies them; Voyager's world is Y-up;
//  * which file to load: the Web3D derivative of the highest quality whose model asset is on disk
//    (Highest, High, Medium, Low, Thumb; AR only when asked for), or the quality asked for;
//  * the view the viewer opens with: the navigation setup's orbit angles (pitch, head, roll in
//    degrees) and offset, as ff-three's CameraController composes them (composeOrbitMatrix:
//    R = Rz(roll) Ry(head) Rx(pitch), eye = R offset, looking along R's -z);
//  * the collection title (metas[].collection.title), the tour's default caption.
// Every key is checked where it is read, and an error names it ("scene.svx.json:
// 'setups[0].navigation.orbit.orbit' must be an array of 3 numbers").
#include <Eigen/Core>

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace meshtour {

/// The derivative qualities of the schema, lowest first (model.schema.json's enum, AR last).
inline constexpr std::string_view kVoyagerQualities[] = {"Thumb", "Low", "Medium", "High", "Highest", "AR"};

/// What a Voyager document says about its model and its opening view.
struct VoyagerDocument {
  std::filesystem::path model_file;  ///< the chosen derivative's Model asset, resolved from the document's folder
  std::string quality;               ///< its quality ("High")
  std::vector<std::string> qualities;  ///< the Web3D qualities the document lists, in its order
  /// Model file coordinates to Voyager's world (Y up, the scene's units): node transforms, the
  /// model's neutral pose and its unit scale.
  Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();
  std::string model_units = "cm";  ///< models[].units ("inherit" resolved to the scene's)
  std::string scene_units = "cm";  ///< setups[].units
  /// The opening view: navigation.orbit.orbit (pitch, head, roll, degrees) and .offset.
  Eigen::Vector3d orbit_deg{-25.0, -25.0, 0.0};
  Eigen::Vector3d offset{0.0, 0.0, 100.0};
  bool orbit_given = false;  ///< false: the document has no orbit and Voyager opens at its default
  std::string title;         ///< metas[].collection.title (or titles.EN), else ""

  /// Unit direction from the orbit's centre to the eye in Voyager's world: R(orbit) · (0, 0, 1).
  Eigen::Vector3d view_direction() const;
};

/// Whether `file` names a Voyager document (ends in ".svx.json", any case).
bool is_voyager_document(const std::filesystem::path& file);

/// Parses a Voyager document. `quality` ("" = the highest on disk; else one of
/// kVoyagerQualities, any case) chooses the Web3D derivative; `exists` says whether an asset file
/// is on disk (std::filesystem::exists by default; the fuzz target says no file exists).
/// \throw InputError naming `source` and the key for malformed or partial documents, and when no
/// Web3D model of the chosen quality is on disk (saying which were looked for).
VoyagerDocument parse_voyager_document(const std::string& json_text, const std::string& source,
                                       const std::filesystem::path& base_dir, std::string_view quality = "",
                                       const std::function<bool(const std::filesystem::path&)>& exists = {});

/// Reads a Voyager document file. \throw IoError if unreadable; else as parse_voyager_document().
VoyagerDocument load_voyager_document(const std::filesystem::path& file, std::string_view quality = "");

}  // namespace meshtour
