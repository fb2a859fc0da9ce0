// Resource limits (tour/resources.h): the estimates grow with the job, the budget check refuses
// with a message that says what to do, byte counts read as people write them, --verbose stages.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "core/error.h"
#include "mesh/mesh.h"
#include "tour/resources.h"

namespace {

using namespace meshtour;
using testing::internal::CaptureStderr;
using testing::internal::GetCapturedStderr;

constexpr double kGiB = 1024.0 * 1024 * 1024;

TEST(TourResources, EstimatesGrowWithTheJob) {
  for (std::size_t triangles : {1'000u, 70'000u, 1'000'000u, 30'000'000u}) {
    const std::size_t more = triangles * 2;
    EXPECT_LT(estimate_mesh_bytes(triangles, triangles / 2), estimate_mesh_bytes(more, more / 2)) << triangles;
    EXPECT_LT(estimate_mesh_bytes(triangles, triangles / 2), estimate_mesh_bytes(triangles, triangles)) << triangles;
    EXPECT_LT(estimate_path_bytes(triangles), estimate_path_bytes(more)) << triangles;
    EXPECT_LT(estimate_shading_bytes(triangles), estimate_shading_bytes(more)) << triangles;
    EXPECT_LT(estimate_ray_scene_bytes(triangles, triangles / 2), estimate_ray_scene_bytes(more, more / 2)) << triangles;
    EXPECT_LT(estimate_coverage_bytes(triangles, triangles / 2), estimate_coverage_bytes(more, more / 2)) << triangles;
  }
  // Frame buffers: with the pixels, the extra layers and the denoiser.
  EXPECT_LT(estimate_frame_bytes(320, 180, 0, false), estimate_frame_bytes(640, 360, 0, false));
  EXPECT_NEAR(estimate_frame_bytes(640, 360, 0, false), 4.0 * estimate_frame_bytes(320, 180, 0, false), 1.0);
  EXPECT_LT(estimate_frame_bytes(640, 360, 0, false), estimate_frame_bytes(640, 360, 3, false));
  EXPECT_LT(estimate_frame_bytes(640, 360, 0, false), estimate_frame_bytes(640, 360, 0, true));
  // An untextured model holds no texels; the cache holds at most 1 GiB of them.
  EXPECT_EQ(estimate_decoded_texture_bytes(TriangleMesh{}), 0.0);
  EXPECT_EQ(estimate_texture_cache_bytes(0.0), 0.0);
  EXPECT_EQ(estimate_texture_cache_bytes(0.5 * kGiB), 0.5 * kGiB);
  EXPECT_EQ(estimate_texture_cache_bytes(8 * kGiB), kGiB);
}

TEST(TourResources, ByteCountsForPeople) {
  EXPECT_EQ(format_bytes(0), "0 B");
  EXPECT_EQ(format_bytes(1023), "1023 B");
  EXPECT_EQ(format_bytes(1024), "1.0 KiB");
  EXPECT_EQ(format_bytes(512.0 * 1024 * 1024), "512.0 MiB");
  EXPECT_EQ(format_bytes(1.5 * kGiB), "1.5 GiB");
  EXPECT_EQ(format_bytes(2048 * kGiB), "2.0 TiB");
}

TEST(TourResources, ABudgetRefusalSaysWhatNeedsMemoryAndHowToRaiseIt) {
  MemoryEstimate estimate;
  estimate.parts = {{"mesh (70000 triangles)", 3.0 * kGiB}, {"frame buffers", 2.0 * kGiB}};
  estimate.peak = 5.0 * kGiB;
  // Within the budget: accepted, also at exactly the budget.
  EXPECT_NO_THROW(check_memory(estimate, MemoryBudget{static_cast<std::uint64_t>(8 * kGiB), "--max-memory 8G"}, "tour"));
  EXPECT_NO_THROW(check_memory(estimate, MemoryBudget{static_cast<std::uint64_t>(5 * kGiB), "--max-memory 5G"}, "tour"));
  try {
    check_memory(estimate, MemoryBudget{static_cast<std::uint64_t>(4 * kGiB), "--max-memory 4G"}, "tour of bunny.ply");
    FAIL() << "a job over its budget was accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "tour of bunny.ply needs an estimated 5.0 GiB of memory (mesh (70000 triangles) 3.0 GiB, frame buffers "
                 "2.0 GiB) but the memory budget is 4.0 GiB (--max-memory 4G); raise it with --max-memory 7G if the "
                 "machine has it, or make the job smaller");
  }
}

TEST(TourResources, VerboseStagesAreReportedAndQuietOnesAreNot) {
  CaptureStderr();
  {
    StageLog quiet(false);
    quiet.start("load");
    quiet.start("path");
    quiet.stop();
    quiet.report("render", 1.5);
    quiet.report_time("encode", 0.5);
  }
  EXPECT_EQ(GetCapturedStderr(), "");

  CaptureStderr();
  {
    StageLog log(true);
    log.start("load");
    log.start("path");  // ends "load"
    log.stop();         // ends "path"
    log.stop();         // nothing running: no line
    log.report_time("encode", 0.5);
  }
  const std::string out = GetCapturedStderr();
  const auto load = out.find("meshtour: stage load "), path = out.find("meshtour: stage path ");
  ASSERT_NE(load, std::string::npos) << out;
  ASSERT_NE(path, std::string::npos) << out;
  EXPECT_LT(load, path);
  EXPECT_NE(out.find("memory "), std::string::npos) << out;
  EXPECT_NE(out.find("meshtour: stage encode              0.500 s\n"), std::string::npos) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 3) << out;
}

}  // namespace
