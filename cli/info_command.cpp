// meshtour info: what a mesh file holds, before anything is rendered (for catalogue pipelines
// that vet files): counts, bounds, a units guess, materials and their textures, colours, UVs,
// boundary edges and components, and the memory a tour of it would need.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <iostream>
#include <memory>
#include <string>

#include "cli/commands.h"
#include "core/error.h"
#include "mesh/mesh.h"
#include "mesh/mesh_statistics.h"
#include "mesh/up_axis.h"
#include "scenes/voyager.h"
#include "cli/scene_args.h"
#include "options/cli_options.h"
#include "tour/resources.h"

namespace meshtour::cli {
namespace {

// A map's key in the JSON: its name with underscores ("metallic-roughness texture" is
// "metallic_roughness_texture").
std::string json_key(std::string kind) {
  std::replace(kind.begin(), kind.end(), ' ', '_');
  std::replace(kind.begin(), kind.end(), '-', '_');
  return kind;
}

struct InfoArgs {
  std::string mesh;
  bool json = false;
  options::Values values;  // info takes no tour settings: stays empty
};

nlohmann::json describe(const std::string& input) {
  // A Voyager document: its highest derivative on disk, posed as the document says.
  std::optional<VoyagerDocument> voyager;
  if (is_voyager_document(input)) voyager = load_voyager_document(input);
  const std::string file = voyager ? voyager->model_file.string() : input;
  const MeshFileSummary counts = check_mesh_file(file);
  LoadReport report;
  // A missing texture is reported, not fatal: info is how one finds out.
  TriangleMesh loaded = load_mesh(file, &report, LoadOptions{.missing_textures_grey = true});
  if (voyager) transform_mesh(loaded, voyager->transform);
  const TriangleMesh& mesh = loaded;
  const Bounds b = mesh.bounds();
  const MeshStatistics stats = mesh_statistics(mesh);
  nlohmann::json j;
  j["file"] = file;
  if (voyager) {
    const Eigen::Vector3d o = voyager->orbit_deg;
    j["voyager"] = {{"document", input}, {"quality", voyager->quality}, {"qualities", voyager->qualities},
                    {"units", voyager->model_units}, {"scene_units", voyager->scene_units}, {"title", voyager->title},
                    {"orbit", {o.x(), o.y(), o.z()}}, {"orbit_given", voyager->orbit_given}};
  }
  j["vertices"] = mesh.vertex_count();
  j["triangles"] = mesh.face_count();
  j["faces_in_file"] = counts.faces;
  j["bounds"] = {{"min", {b.lo.x(), b.lo.y(), b.lo.z()}}, {"max", {b.hi.x(), b.hi.y(), b.hi.z()}}};
  j["units_guess"] = guess_units(b.diagonal());
  j["surface_area"] = stats.surface_area;
  j["vertex_colors"] = mesh.has_colors();
  j["texture_coordinates"] = mesh.corner_uvs.size() == 3 * mesh.triangles.size() && !mesh.triangles.empty();
  j["edges"] = stats.edges;
  j["boundary_edges"] = stats.boundary_edges;
  j["non_manifold_edges"] = stats.non_manifold_edges;
  j["components"] = stats.components;
  j["unreferenced_vertices"] = stats.unreferenced_vertices;
  std::vector<std::size_t> per_material(mesh.materials.size(), 0);
  for (std::size_t t = 0; t < mesh.triangles.size() && !mesh.materials.empty(); ++t)
    ++per_material[mesh.triangle_materials.empty() ? 0 : mesh.triangle_materials[t]];
  j["materials"] = nlohmann::json::array();
  for (std::size_t m = 0; m < mesh.materials.size(); ++m) {
    const MeshMaterial& material = mesh.materials[m];
    nlohmann::json jm = {{"name", material.name}, {"triangles", per_material[m]}};
    if (material.base_color) jm["base_color"] = {material.base_color->x(), material.base_color->y(), material.base_color->z()};
    // Each map with its image's size: "texture", "normal_texture", "occlusion_texture", ...
    for (const auto& [map, kind] : material.named_maps()) {
      const std::string key = json_key(kind);
      jm[key] = map->bytes ? "(embedded) " + map->file.filename().string() : map->file.string();
      const TextureSize size = probe_texture(*map, material.name);
      jm[key + "_size"] = {size.width, size.height, size.channels};
    }
    if (material.metallic_roughness) {
      jm["metallic"] = material.metallic_roughness->metallic;
      jm["roughness"] = material.metallic_roughness->roughness;
    }
    if (material.emissive.squaredNorm() > 0.0f) jm["emissive"] = {material.emissive.x(), material.emissive.y(), material.emissive.z()};
    if (material.unlit) jm["unlit"] = true;
    if (material.alpha_mode != MeshMaterial::AlphaMode::opaque) {
      jm["alpha_mode"] = material.alpha_mode == MeshMaterial::AlphaMode::blend ? "blend" : "mask";
      jm["alpha"] = material.alpha;
      if (material.alpha_mode == MeshMaterial::AlphaMode::mask) jm["alpha_cutoff"] = material.alpha_cutoff;
    }
    if (material.normal_texture.present()) jm["normal_scale"] = material.normal_scale;
    if (material.occlusion_texture.present()) jm["occlusion_strength"] = material.occlusion_strength;
    j["materials"].push_back(jm);
  }
  j["warnings"] = report.warnings;
  // A default tour's parts at 1280x720 (tour/resources.h): the same estimate as `tour` checks.
  const std::size_t triangles = counts.triangles(), vertices = counts.vertices;
  const double texture_bytes = estimate_decoded_texture_bytes(mesh);
  const double texture_cache = estimate_texture_cache_bytes(texture_bytes);
  const MemoryEstimate tour = estimate_job_memory(
      triangles, vertices, {{"ray_tracing_scene", estimate_ray_scene_bytes(triangles, vertices)}},
      MemoryPart{"camera_path", estimate_coverage_bytes(triangles, vertices)},
      {{"shading", estimate_shading_bytes(triangles)}, {"frames_1280x720", estimate_frame_bytes(1280, 720, 0, true)}});
  j["memory_estimate_bytes"] = nlohmann::json::object();
  for (const auto& [part, bytes] : tour.parts)
    if (part != "runtime") j["memory_estimate_bytes"][part] = bytes;
  j["memory_estimate_bytes"]["textures_decoded"] = texture_bytes;
  j["memory_estimate_bytes"]["texture_cache"] = texture_cache;
  j["memory_estimate_bytes"]["peak"] = tour.peak + texture_cache;
  // What --up auto (the default for mesh files) chooses (mesh/up_axis.h), with why; a Voyager
  // model, already posed by its document, is toured +y.
  const UpChoice up = choose_up_axis(mesh, file);
  j["up_axis"] = {{"auto", up.up.name()}, {"confident", up.confident}, {"reason", up.reason}};
  if (!up.warning.empty()) j["up_axis"]["warning"] = up.warning;
  return j;
}

void print_text(const nlohmann::json& j) {
  std::printf("%s\n", j["file"].get<std::string>().c_str());
  if (j.contains("voyager")) {
    const auto& v = j["voyager"];
    std::printf("  Voyager document %s: the %s derivative (of %s), units %s in a %s scene, opening orbit %g, %g, %g; title \"%s\"\n",
                v["document"].get<std::string>().c_str(), v["quality"].get<std::string>().c_str(), v["qualities"].dump().c_str(),
                v["units"].get<std::string>().c_str(), v["scene_units"].get<std::string>().c_str(), v["orbit"][0].get<double>(),
                v["orbit"][1].get<double>(), v["orbit"][2].get<double>(), v["title"].get<std::string>().c_str());
  }
  std::printf("  %zu vertices, %zu triangles (%zu faces in the file)\n", j["vertices"].get<std::size_t>(),
              j["triangles"].get<std::size_t>(), j["faces_in_file"].get<std::size_t>());
  const auto& lo = j["bounds"]["min"];
  const auto& hi = j["bounds"]["max"];
  std::printf("  bounds (%.6g %.6g %.6g) - (%.6g %.6g %.6g); units: %s\n", lo[0].get<double>(), lo[1].get<double>(),
              lo[2].get<double>(), hi[0].get<double>(), hi[1].get<double>(), hi[2].get<double>(),
              j["units_guess"].get<std::string>().c_str());
  std::printf("  vertex colours: %s; texture coordinates: %s\n", j["vertex_colors"].get<bool>() ? "yes" : "no",
              j["texture_coordinates"].get<bool>() ? "yes" : "no");
  std::printf("  %zu components, %zu boundary edges, %zu non-manifold edges, %zu unreferenced vertices\n",
              j["components"].get<std::size_t>(), j["boundary_edges"].get<std::size_t>(),
              j["non_manifold_edges"].get<std::size_t>(), j["unreferenced_vertices"].get<std::size_t>());
  for (const auto& m : j["materials"]) {
    std::printf("  material '%s': %zu triangles", m["name"].get<std::string>().c_str(), m["triangles"].get<std::size_t>());
    // Each map the material has: "texture", "normal texture", ...
    for (const char* kind : kMaterialMapKinds) {
      const std::string map = json_key(kind);
      if (!m.contains(map)) continue;
      const auto& size = m[map + "_size"];
      std::printf(", %s %s (%dx%d, %d channels)", kind, m[map].get<std::string>().c_str(), size[0].get<int>(), size[1].get<int>(),
                  size[2].get<int>());
    }
    if (m.contains("base_color"))
      std::printf(", colour (%g %g %g)", m["base_color"][0].get<double>(), m["base_color"][1].get<double>(), m["base_color"][2].get<double>());
    if (m.contains("alpha_mode")) {
      std::printf(", %s, alpha %g", m["alpha_mode"].get<std::string>().c_str(), m["alpha"].get<double>());
      if (m.contains("alpha_cutoff")) std::printf(" (cut-off %g)", m["alpha_cutoff"].get<double>());
    }
    if (m.contains("metallic")) std::printf(", metallic %g, roughness %g", m["metallic"].get<double>(), m["roughness"].get<double>());
    if (m.contains("emissive"))
      std::printf(", emissive (%g %g %g)", m["emissive"][0].get<double>(), m["emissive"][1].get<double>(), m["emissive"][2].get<double>());
    if (m.contains("unlit")) std::printf(", unlit");
    std::printf("\n");
  }
  for (const auto& w : j["warnings"]) std::printf("  warning: %s\n", w.get<std::string>().c_str());
  const auto& mem = j["memory_estimate_bytes"];
  std::printf("  a 1280x720 tour needs about %.0f MB at its peak (textures: %.0f MB decoded, of which the texture cache\n"
              "  holds at most %.0f MB)\n",
              mem["peak"].get<double>() / 1e6, mem["textures_decoded"].get<double>() / 1e6, mem["texture_cache"].get<double>() / 1e6);
  std::printf("  up axis (--up auto): %s, %s\n", j["up_axis"]["auto"].get<std::string>().c_str(),
              j["up_axis"]["reason"].get<std::string>().c_str());
  if (j["up_axis"].contains("warning")) std::printf("  warning: %s\n", j["up_axis"]["warning"].get<std::string>().c_str());
}

}  // namespace

void add_info_command(CLI::App& app) {
  auto args = std::make_shared<InfoArgs>();
  CLI::App* cmd = app.add_subcommand("info", "Describe a mesh file without rendering it (counts, bounds, materials, textures, memory).");
  add_mesh_argument(*cmd, args->mesh);
  options::add_command_options(*cmd, options::info, args->values, {{"json", options::to(args->json)}});
  cmd->callback([args] {
    const nlohmann::json j = describe(args->mesh);
    if (args->json) std::cout << j.dump(1) << "\n";
    else print_text(j);
  });
}

}  // namespace meshtour::cli
