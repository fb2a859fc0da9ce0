// Golden-image tests of the built-in default scene on the turntable, compared with golden_images/
// (metric, thresholds, diff images and the GOLDEN_UPDATE=1 switch: tests/golden.h).
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <cstdlib>

#include "golden.h"
#include "helpers.h"
#include "pathgen/turntable.h"
#include "scenes/scene.h"
#include "tracer/tracer.h"

namespace meshtour {
namespace {

// Fraction of pixels allowed to fail (see tests/golden.h): 0.5 %: a few silhouette pixels may differ across CPUs.
void default_scene_golden(const Image& image, const std::string& name) { test::compare_with_golden(image, name, 0.005); }


class DefaultScene : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    scene_ = new Scene(default_scene());
    scene_->render.width = 160;
    scene_->render.height = 120;
    mesh_ = new TriangleMesh(load_scene_model(*scene_));
    TurntableOptions options;
    options.up = scene_->up;
    options.elevation_deg = scene_->elevation_deg;
    options.lens.vertical_fov_deg = scene_->vertical_fov_deg;
    options.lens.aspect = 160.0 / 120.0;
    path_ = new TurntablePath(mesh_->positions, options);
    scene_->render.world_up = scene_->up.vector();
    renderer_ = new Renderer(*mesh_, scene_->render);
  }
  static void TearDownTestSuite() {
    delete renderer_;
    delete path_;
    delete mesh_;
    delete scene_;
  }
  static Image frame(int k) {
    const CameraPose pose = frame_pose(*path_, k, scene_->frames);
    return renderer_->render(Camera::at(pose, scene_->vertical_fov_deg), static_cast<std::uint64_t>(k));
  }
  static inline Scene* scene_ = nullptr;
  static inline TriangleMesh* mesh_ = nullptr;
  static inline TurntablePath* path_ = nullptr;
  static inline Renderer* renderer_ = nullptr;
};

TEST_F(DefaultScene, TurntableFrontView) { default_scene_golden(frame(0), "default_scene_turntable_f000"); }
TEST_F(DefaultScene, TurntableQuarterTurn) { default_scene_golden(frame(30), "default_scene_turntable_f030"); }

}  // namespace
}  // namespace meshtour
