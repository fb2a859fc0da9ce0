#include "scenes/voyager.h"

#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <set>

#include "core/error.h"
#include "core/json_reader.h"

namespace meshtour {
namespace {

using nlohmann::json;

std::string lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string indexed(const std::string& key, std::size_t i) { return key + "[" + std::to_string(i) + "]"; }

// Metres per unit of common.schema.json's units (Voyager's utils/unitScaleFactor).
std::optional<double> metres_per_unit(const std::string& units) {
  static const std::pair<const char*, double> kUnits[] = {{"mm", 0.001},   {"cm", 0.01},   {"m", 1.0},
                                                          {"km", 1000.0},  {"in", 0.0254}, {"ft", 0.3048},
                                                          {"yd", 0.9144},  {"mi", 1609.344}};
  for (const auto& [name, metres] : kUnits)
    if (units == name) return metres;
  return std::nullopt;
}

// An array of `count` finite numbers at `key` of `r`.
std::vector<double> fixed_numbers(JsonReader& r, const std::string& key, std::size_t count) {
  const json& v = r.raw(key);
  if (!v.is_array() || v.size() != count || !std::all_of(v.begin(), v.end(), [](const json& e) { return e.is_number(); }))
    r.fail_key(key, "must be an array of " + std::to_string(count) + " numbers");
  std::vector<double> out = r.numbers(key);  // rejects non-finite values
  return out;
}

// An index into the document's array `array` (of `size` elements) at `key` of `r`.
std::size_t index_into(JsonReader& r, const std::string& key, const char* array, std::size_t size) {
  if (size == 0) r.fail_key(key, std::string("refers to '") + array + "', which the document does not have");
  return static_cast<std::size_t>(r.integer(key, 0, static_cast<long long>(size) - 1));
}

// The array member `key` of the document (empty when absent); anything but an array is an error.
const json& array_member(JsonReader& top, const json& doc, const std::string& key) {
  static const json kEmpty = json::array();
  if (!top.has(key)) return kEmpty;
  const json& v = doc.at(key);
  if (!v.is_array()) top.fail_key(key, "must be an array");
  return v;
}

// A node's local transform: its column-major "matrix", or translation · rotation · scale.
Eigen::Matrix4d node_transform(JsonReader& node) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  if (node.has("matrix")) {
    for (const char* trs : {"translation", "rotation", "scale"})
      if (node.has(trs)) node.fail_key(trs, "cannot be given with 'matrix' (the schema allows one or the other)");
    const std::vector<double> e = fixed_numbers(node, "matrix", 16);
    for (int col = 0; col < 4; ++col)
      for (int row = 0; row < 4; ++row) m(row, col) = e[static_cast<std::size_t>(4 * col + row)];
    if (m(3, 0) != 0.0 || m(3, 1) != 0.0 || m(3, 2) != 0.0 || m(3, 3) != 1.0)
      node.fail_key("matrix", "must be an affine transform (its last row 0, 0, 0, 1; column-major order)");
    return m;
  }
  Eigen::Affine3d a = Eigen::Affine3d::Identity();
  if (node.has("translation")) {
    const std::vector<double> t = fixed_numbers(node, "translation", 3);
    a.translate(Eigen::Vector3d(t[0], t[1], t[2]));
  }
  if (node.has("rotation")) {
    const std::vector<double> q = fixed_numbers(node, "rotation", 4);
    const Eigen::Quaterniond quat(q[3], q[0], q[1], q[2]);  // stored (x, y, z, w)
    if (!(quat.norm() > 1e-6)) node.fail_key("rotation", "must be a unit quaternion (x, y, z, w), got a zero one");
    a.rotate(quat.normalized());
  }
  if (node.has("scale")) {
    const std::vector<double> s = fixed_numbers(node, "scale", 3);
    if (s[0] == 0.0 || s[1] == 0.0 || s[2] == 0.0) node.fail_key("scale", "must not be zero along any axis");
    a.scale(Eigen::Vector3d(s[0], s[1], s[2]));
  }
  return a.matrix();
}

// The node tree under the scene's roots: each node that carries a model, with its world
// transform (the product of the transforms from its root down).
struct ModelNode {
  std::size_t node = 0, model = 0;
  Eigen::Matrix4d world = Eigen::Matrix4d::Identity();
  std::optional<std::size_t> meta;
};

// Each node is visited once (a node with two parents is refused), so a document's size bounds the
// work; the depth is bounded too, so that a long chain of children cannot exhaust the stack.
void walk_nodes(const json& nodes, const std::string& source, std::size_t index, const Eigen::Matrix4d& parent,
                std::set<std::size_t>& seen, int depth, std::size_t models, std::size_t metas, std::vector<ModelNode>& out) {
  JsonReader node(nodes[index], source, indexed("nodes", index));
  if (depth > 256) node.fail("lies more than 256 levels below the scene's root (the node tree is too deep)");
  seen.insert(index);
  const Eigen::Matrix4d world = parent * node_transform(node);
  if (node.has("model")) {
    ModelNode m{index, index_into(node, "model", "models", models), world, std::nullopt};
    if (node.has("meta")) m.meta = index_into(node, "meta", "metas", metas);
    out.push_back(m);
  }
  if (!node.has("children")) return;
  const json& children = node.raw("children");
  if (!children.is_array()) node.fail_key("children", "must be an array of node indices");
  for (std::size_t k = 0; k < children.size(); ++k) {
    if (!children[k].is_number_integer() || children[k].get<long long>() < 0 ||
        children[k].get<long long>() >= static_cast<long long>(nodes.size()))
      node.fail_key(indexed("children", k), "must be the index of a node (0 to " + std::to_string(nodes.size() - 1) + ")");
    const auto child = static_cast<std::size_t>(children[k].get<long long>());
    if (seen.contains(child))
      node.fail_key(indexed("children", k), "names node " + std::to_string(child) + ", which is already in the scene's tree (the nodes must form a tree)");
    walk_nodes(nodes, source, child, world, seen, depth + 1, models, metas, out);
  }
}

// The title of a meta component: collection.title, else collection.titles (English first).
std::string meta_title(const json& meta, const std::string& source, const std::string& path) {
  JsonReader m(meta, source, path);
  if (!m.has("collection")) return "";
  JsonReader collection = m.child("collection");
  std::string title;
  collection.read("title", title);
  if (!title.empty() || !collection.has("titles")) return title;
  const json& titles = collection.raw("titles");
  if (!titles.is_object()) collection.fail_key("titles", "must be an object of titles by language, e.g. {\"EN\": \"Bell\"}");
  for (const char* english : {"EN", "en"})
    if (titles.contains(english) && titles[english].is_string()) return titles[english].get<std::string>();
  for (const auto& [language, text] : titles.items())
    if (text.is_string()) return text.get<std::string>();
  return "";
}

}  // namespace

Eigen::Vector3d VoyagerDocument::view_direction() const {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  // composeOrbitMatrix's third column: R = Rz(roll) Ry(head) Rx(pitch) applied to +z.
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(orbit_deg.z() * kDeg, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(orbit_deg.y() * kDeg, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(orbit_deg.x() * kDeg, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  return r.col(2).normalized();
}

bool is_voyager_document(const std::filesystem::path& file) {
  const std::string name = lower(file.filename().string());
  return name.size() > 9 && name.ends_with(".svx.json");
}

VoyagerDocument parse_voyager_document(const std::string& json_text, const std::string& source,
                                       const std::filesystem::path& base_dir, std::string_view quality,
                                       const std::function<bool(const std::filesystem::path&)>& exists) {
  const json doc = parse_json_document(json_text, source);
  JsonReader top(doc, source, "");
  VoyagerDocument out;

  // asset: says that this is a Voyager document at all.
  {
    JsonReader asset = top.child("asset");
    std::string type;
    asset.read("type", type);
    if (type != "application/si-dpo-3d.document+json")
      asset.fail_key("type", "must be \"application/si-dpo-3d.document+json\" (a Smithsonian Voyager document), got \"" + type + "\"");
  }

  const json& scenes = array_member(top, doc, "scenes");
  const json& nodes = array_member(top, doc, "nodes");
  const json& models = array_member(top, doc, "models");
  const json& setups = array_member(top, doc, "setups");
  const json& metas = array_member(top, doc, "metas");
  if (scenes.empty()) top.fail_key("scenes", top.has("scenes") ? "is empty" : "is missing");
  const std::size_t scene_index = index_into(top, "scene", "scenes", scenes.size());
  JsonReader scene(scenes[scene_index], source, indexed("scenes", scene_index));

  // The node tree and the one model in it.
  std::vector<ModelNode> found;
  std::set<std::size_t> seen;
  if (scene.has("nodes")) {
    const json& roots = scene.raw("nodes");
    if (!roots.is_array()) scene.fail_key("nodes", "must be an array of node indices");
    for (std::size_t k = 0; k < roots.size(); ++k) {
      if (!roots[k].is_number_integer() || roots[k].get<long long>() < 0 || roots[k].get<long long>() >= static_cast<long long>(nodes.size()))
        scene.fail_key(indexed("nodes", k), nodes.empty() ? "refers to 'nodes', which the document does not have"
                                                          : "must be the index of a node (0 to " + std::to_string(nodes.size() - 1) + ")");
      const auto root = static_cast<std::size_t>(roots[k].get<long long>());
      if (seen.contains(root)) scene.fail_key(indexed("nodes", k), "names node " + std::to_string(root) + " twice (the nodes must form a tree)");
      walk_nodes(nodes, source, root, Eigen::Matrix4d::Identity(), seen, 0, models.size(), metas.size(), found);
    }
  }
  if (found.empty())
    scene.fail("has no node with a model ('nodes' of the scene, then their 'children', must reach a node with \"model\": INDEX)");
  if (found.size() > 1)
    scene.fail("has " + std::to_string(found.size()) + " nodes with a model (nodes " + std::to_string(found[0].node) + " and " +
               std::to_string(found[1].node) + ", ...); meshtour tours one model: give the derivative's file itself");
  const ModelNode& placed = found.front();

  // The setup: the scene's units and the opening view.
  std::optional<std::size_t> setup_index;
  if (scene.has("setup")) setup_index = index_into(scene, "setup", "setups", setups.size());
  else if (!setups.empty()) setup_index = 0;
  if (setup_index) {
    const std::string path = indexed("setups", *setup_index);
    JsonReader setup(setups[*setup_index], source, path);
    setup.read("units", out.scene_units);
    if (!metres_per_unit(out.scene_units)) setup.fail_key("units", "must be one of mm, cm, m, km, in, ft, yd, mi, got \"" + out.scene_units + "\"");
    if (setup.has("navigation")) {
      JsonReader navigation = setup.child("navigation");
      if (navigation.has("orbit")) {
        JsonReader orbit = navigation.child("orbit");
        const std::vector<double> angles = fixed_numbers(orbit, "orbit", 3);
        out.orbit_deg = Eigen::Vector3d(angles[0], angles[1], angles[2]);
        out.orbit_given = true;
        if (orbit.has("offset")) {
          const std::vector<double> offset = fixed_numbers(orbit, "offset", 3);
          out.offset = Eigen::Vector3d(offset[0], offset[1], offset[2]);
        }
      }
    }
  }

  // The model: units, neutral pose, derivatives.
  const std::string model_path = indexed("models", placed.model);
  JsonReader model(models[placed.model], source, model_path);
  {
    const json& units = model.raw("units");
    if (!units.is_string()) model.fail_key("units", "must be a string (mm, cm, m, km, in, ft, yd, mi or inherit)");
    out.model_units = units.get<std::string>();
    if (out.model_units == "inherit") out.model_units = out.scene_units;
    if (!metres_per_unit(out.model_units))
      model.fail_key("units", "must be one of mm, cm, m, km, in, ft, yd, mi or inherit, got \"" + out.model_units + "\"");
  }
  const double unit_scale = *metres_per_unit(out.model_units) / *metres_per_unit(out.scene_units);
  Eigen::Affine3d pose = Eigen::Affine3d::Identity();
  // CVModel2: position and quaternion composed with the unit scale, position scaled by it too.
  if (model.has("translation")) {
    const std::vector<double> t = fixed_numbers(model, "translation", 3);
    pose.translate(unit_scale * Eigen::Vector3d(t[0], t[1], t[2]));
  }
  if (model.has("rotation")) {
    const std::vector<double> q = fixed_numbers(model, "rotation", 4);
    const Eigen::Quaterniond quat(q[3], q[0], q[1], q[2]);
    if (!(quat.norm() > 1e-6)) model.fail_key("rotation", "must be a unit quaternion (x, y, z, w), got a zero one");
    pose.rotate(quat.normalized());
  }
  pose.scale(unit_scale);
  out.transform = placed.world * pose.matrix();

  const json& derivatives = model.raw("derivatives");
  if (!derivatives.is_array()) model.fail_key("derivatives", "must be an array of derivatives");
  // Web3D derivatives with a Model asset, by quality.
  struct Candidate {
    std::string quality;
    std::filesystem::path file;
  };
  std::vector<Candidate> web;
  for (std::size_t i = 0; i < derivatives.size(); ++i) {
    JsonReader d(derivatives[i], source, model_path + "." + indexed("derivatives", i));
    std::string usage, q;
    d.read("usage", usage);
    d.read("quality", q);
    if (usage != "Web3D") continue;
    if (std::find(std::begin(kVoyagerQualities), std::end(kVoyagerQualities), q) == std::end(kVoyagerQualities))
      d.fail_key("quality", "must be one of Thumb, Low, Medium, High, Highest, AR, got \"" + q + "\"");
    const json& assets = d.raw("assets");
    if (!assets.is_array()) d.fail_key("assets", "must be an array of assets");
    for (std::size_t k = 0; k < assets.size(); ++k) {
      JsonReader a(assets[k], source, model_path + "." + indexed("derivatives", i) + "." + indexed("assets", k));
      std::string type;
      a.read("type", type);
      if (type != "Model") continue;
      std::string uri;
      a.read("uri", uri);
      if (uri.empty()) a.fail_key("uri", "must name the model's file (relative to the document)");
      if (uri.find("://") != std::string::npos)
        a.fail_key("uri", "is a URL (" + uri + "); meshtour reads files: download it next to the document and name it relatively");
      const std::filesystem::path p(uri);
      web.push_back({q, p.is_absolute() ? p : base_dir / p});
      break;  // one model asset per derivative
    }
    out.qualities.push_back(q);
  }
  if (web.empty()) model.fail_key("derivatives", "has no Web3D derivative with a Model asset (usage \"Web3D\", an asset of type \"Model\")");

  const auto on_disk = [&](const std::filesystem::path& p) { return exists ? exists(p) : std::filesystem::exists(p); };
  std::string tried;
  const auto pick = [&](std::string_view wanted) -> bool {
    for (const Candidate& c : web)
      if (c.quality == wanted) {
        tried += (tried.empty() ? "" : ", ") + c.quality + " (" + c.file.string() + ")";
        if (on_disk(c.file)) {
          out.model_file = c.file;
          out.quality = c.quality;
          return true;
        }
      }
    return false;
  };
  if (!quality.empty()) {
    const std::string wanted = lower(quality);
    const auto it = std::find_if(std::begin(kVoyagerQualities), std::end(kVoyagerQualities),
                                 [&](std::string_view q) { return lower(q) == wanted; });
    if (it == std::end(kVoyagerQualities)) throw InputError("--quality " + std::string(quality) + ": use Thumb, Low, Medium, High, Highest or AR");
    if (!pick(*it)) {
      std::string listed;
      for (const Candidate& c : web) listed += (listed.empty() ? "" : ", ") + c.quality;
      throw InputError(source + ": " + (tried.empty() ? "no Web3D derivative of quality " + std::string(*it) + " (it lists " + listed + ")"
                                                      : "the " + std::string(*it) + " derivative's model is not on disk: " + tried));
    }
  } else {
    // Highest first; AR derivatives (made for phones' AR viewers) only when asked for.
    bool chosen = false;
    for (int q = 4; q >= 0 && !chosen; --q) chosen = pick(kVoyagerQualities[q]);
    if (!chosen)
      throw InputError(source + ": no Web3D derivative's model is on disk (looked for " + (tried.empty() ? std::string("none but AR") : tried) +
                       "); download one next to the document, or choose AR with --quality AR");
  }

  // The title: the model node's meta, else the scene's, else the first.
  std::optional<std::size_t> meta = placed.meta;
  if (!meta && scene.has("meta")) meta = index_into(scene, "meta", "metas", metas.size());
  if (!meta && !metas.empty()) meta = 0;
  if (meta) out.title = meta_title(metas[*meta], source, indexed("metas", *meta));
  return out;
}

VoyagerDocument load_voyager_document(const std::filesystem::path& file, std::string_view quality) {
  return parse_voyager_document(read_json_file_text(file, "Voyager document"), file.string(), file.parent_path(), quality);
}

}  // namespace meshtour
