// Golden-image tests: renders compared with the references in golden_images/.
//
// Metric (OpenImageIO's ImageBufAlgo::compare, the same as idiff) on 8-bit sRGB PNGs:
//  - a pixel "fails" when any channel differs by more than 2/255: the reference may come from
//    another CPU where Embree's traversal or libm round a silhouette pixel differently;
//  - the test fails when more than 0.5 % of the pixels fail (a few edge pixels may differ across
//    CPUs, a real change of shading, framing or geometry moves far more), or when any pixel
//    differs by more than 0.25 (a missing or misplaced part of the model, whatever its size).
// On failure the actual image and a x16 difference image are written next to the build.
//
// To regenerate the references on purpose (after a deliberate change to the look):
//   GOLDEN_UPDATE=1 ctest --test-dir build -L golden
// then look at the new images and commit them.
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <cstdlib>

#include "helpers.h"
#include "pathgen/turntable.h"
#include "scenes/scene.h"
#include "tracer/tracer.h"

namespace meshtour {
namespace {

constexpr float kPixelFail = 2.0f / 255.0f;
constexpr double kFailFraction = 0.005;
constexpr float kHardFail = 0.25f;

bool updating() {
  const char* v = std::getenv("GOLDEN_UPDATE");
  return v && std::string(v) == "1";
}

void compare_with_golden(const Image& image, const std::string& name) {
  const auto golden = test::source_dir() / "golden_images" / (name + ".png");
  const auto out_dir = std::filesystem::path(MESHTOUR_BINARY_DIR) / "golden-results";
  std::filesystem::create_directories(out_dir);
  const auto actual_file = out_dir / (name + ".actual.png");
  write_image(image, actual_file);
  if (updating()) {
    std::filesystem::create_directories(golden.parent_path());
    std::filesystem::copy_file(actual_file, golden, std::filesystem::copy_options::overwrite_existing);
    GTEST_SKIP() << "GOLDEN_UPDATE=1: rewrote " << golden;
  }
  ASSERT_TRUE(std::filesystem::exists(golden)) << golden << " is missing; create it with GOLDEN_UPDATE=1";
  OIIO::ImageBuf actual(actual_file.string()), reference(golden.string());
  ASSERT_TRUE(actual.read() && reference.read()) << actual.geterror() << reference.geterror();
  ASSERT_EQ(actual.spec().width, reference.spec().width);
  ASSERT_EQ(actual.spec().height, reference.spec().height);
  const auto result = OIIO::ImageBufAlgo::compare(actual, reference, kPixelFail, kPixelFail);
  const double pixels = static_cast<double>(actual.spec().width) * actual.spec().height;
  const double failing = static_cast<double>(result.nfail) / pixels;
  const bool ok = failing <= kFailFraction && result.maxerror <= kHardFail;
  if (!ok) {
    OIIO::ImageBuf diff = OIIO::ImageBufAlgo::absdiff(actual, reference);
    diff = OIIO::ImageBufAlgo::mul(diff, 16.0f);
    diff.write((out_dir / (name + ".diff.png")).string());
  }
  EXPECT_TRUE(ok) << name << ": " << result.nfail << " pixels (" << 100 * failing << " %) differ by more than 2/255"
                  << ", max error " << result.maxerror << " at (" << result.maxx << ", " << result.maxy << ")"
                  << ", mean error " << result.meanerror << "; see " << out_dir / (name + ".diff.png")
                  << " and " << actual_file;
}

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
    return renderer_->render(Camera{pose.eye, pose.target, pose.up, scene_->vertical_fov_deg}, static_cast<std::uint64_t>(k));
  }
  static inline Scene* scene_ = nullptr;
  static inline TriangleMesh* mesh_ = nullptr;
  static inline TurntablePath* path_ = nullptr;
  static inline Renderer* renderer_ = nullptr;
};

TEST_F(DefaultScene, TurntableFrontView) { compare_with_golden(frame(0), "default_scene_turntable_f000"); }
TEST_F(DefaultScene, TurntableQuarterTurn) { compare_with_golden(frame(30), "default_scene_turntable_f030"); }

}  // namespace
}  // namespace meshtour
