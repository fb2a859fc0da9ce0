#include "cli/render_options.h"

namespace meshtour::cli {

void add_render_options(CLI::App& cmd, RenderArgs& args) {
  cmd.add_option("--preset", args.preset,
                 "Look: studio (key, fill and rim lights, soft shadows, ambient occlusion, shadow-catching ground, "
                 "gradient) or plain (even light, no shadows, for catalogues); the scene file's own look values still apply "
                 "(default: the scene's, else studio)")
      ->check(CLI::IsMember({"studio", "plain"}));
  cmd.add_option("--spp", args.spp, "Samples per pixel, stratified; noise falls as 1/sqrt(spp) (default 16)")
      ->check(CLI::Range(1, 4096));
  cmd.add_option("--background", args.background,
                 "gradient, or transparent (PNG frames get alpha; the ground's shadows stay, as alpha)")
      ->check(CLI::IsMember({"gradient", "transparent"}));
  cmd.add_option("--exposure", args.exposure, "Exposure in stops for PNG frames and the video (EXR stays linear)")
      ->check(CLI::Range(-20.0, 20.0));
  cmd.add_option("--exr-layers", args.exr_layers, "Extra layers in EXR frames: albedo, normal, depth (alpha is always there)")
      ->check(CLI::IsMember({"albedo", "normal", "depth"}))
      ->delimiter(',');
}

void apply_render_options(const RenderArgs& args, Scene& scene) {
  if (args.preset) set_look_preset(scene, *args.preset);
  if (args.spp) scene.render.samples_per_pixel = *args.spp;
  if (args.background)
    scene.render.shading.background = *args.background == "transparent" ? BackgroundKind::transparent : BackgroundKind::gradient;
  if (args.exposure) scene.render.shading.exposure = static_cast<float>(*args.exposure);
  for (const auto& layer : args.exr_layers) {
    if (layer == "albedo") scene.render.layers.albedo = true;
    if (layer == "normal") scene.render.layers.normal = true;
    if (layer == "depth") scene.render.layers.depth = true;
  }
  // The ground lies under the model's up axis, whichever way the file or --up gave it.
  scene.render.world_up = scene.up.vector();
}

}  // namespace meshtour::cli
