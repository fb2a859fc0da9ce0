// Frame selections (A, A-B, A-B:S, lists; clamped to the tour) and the frames-directory manifest.
#include <gtest/gtest.h>

#include <fstream>

#include "core/error.h"
#include "helpers.h"
#include "jobs/frame_dir.h"
#include "jobs/frame_range.h"

namespace meshtour {
namespace {

std::vector<int> iota(int a, int b) {
  std::vector<int> v;
  for (int k = a; k <= b; ++k) v.push_back(k);
  return v;
}

TEST(FrameRange, AllAndEmptySelectEveryFrame) {
  EXPECT_EQ(parse_frame_range("all", 5), iota(0, 4));
  EXPECT_EQ(parse_frame_range("", 3), iota(0, 2));
}

TEST(FrameRange, SingleRangeStepAndList) {
  EXPECT_EQ(parse_frame_range("7", 10), std::vector<int>{7});
  EXPECT_EQ(parse_frame_range("2-5", 10), iota(2, 5));
  EXPECT_EQ(parse_frame_range("0-9:3", 10), (std::vector<int>{0, 3, 6, 9}));
  EXPECT_EQ(parse_frame_range("1-8:3", 10), (std::vector<int>{1, 4, 7}));
  EXPECT_EQ(parse_frame_range(" 9, 1-2 ,5 ", 10), (std::vector<int>{1, 2, 5, 9}));
}

TEST(FrameRange, OverlapsAreMergedAndSorted) {
  EXPECT_EQ(parse_frame_range("4-6,0-5,5", 10), iota(0, 6));
}

TEST(FrameRange, ClampedToTheTour) {
  EXPECT_EQ(parse_frame_range("100-199", 150), iota(100, 149));
  EXPECT_TRUE(parse_frame_range("200-299", 150).empty());  // a farm's surplus chunk selects nothing
  EXPECT_EQ(parse_frame_range("140-1000:5", 150), (std::vector<int>{140, 145}));
}

TEST(FrameRange, MalformedSelectionsNameThePart) {
  for (const char* bad : {"a", "1-", "-3", "5-2", "1-9:0", "1-9:-2", "1,,2", "3:2", "1.5", "2-3-4", "99999999999", "0x10"}) {
    try {
      parse_frame_range(bad, 100);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("frame selection"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(parse_frame_range("all", 0), InputError);
}

TEST(FrameRange, FormatIsTheInverse) {
  const std::vector<int> frames{0, 1, 2, 3, 7, 9, 10};
  EXPECT_EQ(format_frame_range(frames), "0-3,7,9-10");
  EXPECT_EQ(parse_frame_range(format_frame_range(frames), 11), frames);
  EXPECT_EQ(format_frame_range({}), "");
}

TEST(FrameDir, FrameNamesAreZeroPadded) {
  EXPECT_EQ(frame_file("/x", 123, "exr"), std::filesystem::path("/x/frame_000123.exr"));
  EXPECT_EQ(frame_file("d", 1234567, "png"), std::filesystem::path("d/frame_1234567.png"));
}

TEST(FrameDir, ManifestRoundTripsAndMissingFramesAreListed) {
  const auto dir = test::scratch_dir();
  FrameDirInfo info;
  info.frame_count = 12;
  info.fps = 24;
  info.width = 64;
  info.height = 48;
  info.image_formats = {"png", "exr"};
  info.source = "bunny.ply";
  write_frame_dir_info(dir, info);
  const FrameDirInfo back = read_frame_dir_info(dir);
  EXPECT_TRUE(back.same_tour(info));
  EXPECT_EQ(back.source, "bunny.ply");
  for (int k : {0, 2, 3}) std::ofstream(frame_file(dir, k, "png")) << "x";
  EXPECT_EQ(missing_frames(dir, iota(0, 4), "png"), (std::vector<int>{1, 4}));
  FrameDirInfo other = info;
  other.width = 66;
  EXPECT_FALSE(back.same_tour(other));
  EXPECT_TRUE(back.view_scores.empty());
  EXPECT_EQ(back.best_view_frame, -1);
  // The view scores of the path search and the best frame's index round-trip (informative only).
  FrameDirInfo scored = info;
  scored.view_scores = {0.5, 0.75, 0.25, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.0, 0.125};
  scored.best_view_frame = 1;
  write_frame_dir_info(dir, scored);
  const FrameDirInfo again = read_frame_dir_info(dir);
  EXPECT_EQ(again.view_scores, scored.view_scores);
  EXPECT_EQ(again.best_view_frame, 1);
  EXPECT_TRUE(again.same_tour(info));
}

TEST(FrameDir, BadManifestsAreInputErrors) {
  const auto dir = test::scratch_dir();
  EXPECT_THROW(read_frame_dir_info(dir), InputError);  // missing
  const auto write = [&](const std::string& text) { std::ofstream(dir / std::string(kFrameDirManifestName)) << text; };
  write("{not json");
  EXPECT_THROW(read_frame_dir_info(dir), InputError);
  write(R"({"format":"meshtour-frames","version":99,"frame_count":3,"fps":30,"width":8,"height":8,"image_formats":["png"]})");
  try {
    read_frame_dir_info(dir);
    ADD_FAILURE() << "accepted a newer manifest";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("newer"), std::string::npos) << e.what();
  }
  write(R"({"format":"meshtour-frames","version":1,"frame_count":-3,"fps":30,"width":8,"height":8,"image_formats":["png"]})");
  EXPECT_THROW(read_frame_dir_info(dir), InputError);
  write(R"({"format":"meshtour-frames","version":1,"frame_count":3,"fps":30,"width":8,"height":8,"image_formats":["tiff"]})");
  EXPECT_THROW(read_frame_dir_info(dir), InputError);
  // View scores: one number per frame, and a best frame inside the tour.
  write(R"({"format":"meshtour-frames","version":1,"frame_count":3,"fps":30,"width":8,"height":8,"image_formats":["png"],"view_scores":[1,2],"best_view_frame":1})");
  EXPECT_THROW(read_frame_dir_info(dir), InputError);
  write(R"({"format":"meshtour-frames","version":1,"frame_count":3,"fps":30,"width":8,"height":8,"image_formats":["png"],"view_scores":[1,2,"x"],"best_view_frame":1})");
  EXPECT_THROW(read_frame_dir_info(dir), InputError);
  write(R"({"format":"meshtour-frames","version":1,"frame_count":3,"fps":30,"width":8,"height":8,"image_formats":["png"],"view_scores":[1,2,3],"best_view_frame":3})");
  EXPECT_THROW(read_frame_dir_info(dir), InputError);
}

}  // namespace
}  // namespace meshtour
