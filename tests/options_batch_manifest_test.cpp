// Batch manifests (CSV with a header row, or JSON): columns, defaults, quoting, and bad values
// that fail only their own item.
#include <gtest/gtest.h>

#include <fstream>

#include "core/error.h"
#include "helpers.h"
#include "options/batch_manifest.h"
#include "jobs/frame_dir.h"

namespace meshtour {
namespace {

std::filesystem::path write(const std::filesystem::path& file, const std::string& text) {
  std::ofstream(file) << text;
  return file;
}

TEST(BatchManifest, CsvColumnsDefaultsQuotingAndComments) {
  const auto dir = test::scratch_dir();
  const auto items = read_batch_manifest(write(dir / "m.csv",
                                               "# catalogue\r\n"
                                               "Mesh, up ,output,preset,frames,width,height,fps,spp,path,seconds\r\n"
                                               "a.ply,Z,,plain,24,640,360,25,4,turntable,\r\n"
                                               "\r\n"
                                               "\"sub dir/b, c.obj\",,b.mp4,,,,,,,,2.5\r\n"
                                               "/abs/c.stl\r\n"));
  ASSERT_EQ(items.size(), 3u);
  EXPECT_EQ(items[0].mesh, dir / "a.ply");  // relative to the manifest's folder
  EXPECT_EQ(items[0].output, "a.mp4");       // default: the mesh's name
  EXPECT_EQ(items[0].values.at("up"), "z");
  EXPECT_EQ(items[0].values.at("preset"), "plain");
  EXPECT_EQ(items[0].values.at("path"), "turntable");
  EXPECT_EQ(items[0].values.at("frame-count"), "24");
  EXPECT_EQ(items[0].values.at("width"), "640");
  EXPECT_EQ(items[0].values.at("height"), "360");
  EXPECT_EQ(items[0].values.at("fps"), "25");
  EXPECT_EQ(items[0].values.at("spp"), "4");
  EXPECT_EQ(items[0].line, 3);
  EXPECT_EQ(items[1].mesh, dir / "sub dir/b, c.obj");
  EXPECT_EQ(items[1].output, "b.mp4");
  EXPECT_EQ(items[1].values.count("up"), 0u);
  EXPECT_EQ(items[1].values.at("seconds"), "2.5");
  EXPECT_EQ(items[2].mesh, std::filesystem::path("/abs/c.stl"));
  EXPECT_EQ(items[2].index, 2);
  for (const auto& i : items) EXPECT_EQ(i.error, "") << i.index;
}

TEST(BatchManifest, BadValuesMakeOnlyTheirItemBad) {
  const auto dir = test::scratch_dir();
  const auto items = read_batch_manifest(write(dir / "m.csv",
                                               "mesh,up,width,output\n"
                                               "a.ply,w,,\n"
                                               "b.ply,y,12x,\n"
                                               "c.ply,y,64,x/c.mp4\n"
                                               "d.ply,y,64,d.avi\n"
                                               "e.ply,y,64,h.mp4\n"
                                               ",y,64,f.mp4\n"
                                               "g.ply,y,64,g.mp4,extra\n"
                                               "h.ply\n"));
  ASSERT_EQ(items.size(), 8u);
  EXPECT_NE(items[0].error.find("up 'w'"), std::string::npos);
  EXPECT_NE(items[1].error.find("width '12x'"), std::string::npos);
  EXPECT_NE(items[2].error.find("plain file name"), std::string::npos);
  EXPECT_NE(items[3].error.find("must end in .mp4"), std::string::npos);
  EXPECT_EQ(items[4].error, "");
  EXPECT_EQ(items[5].error, "no mesh given");
  EXPECT_NE(items[6].error.find("fields"), std::string::npos);
  EXPECT_NE(items[7].error.find("output 'h.mp4' is already used by item 4"), std::string::npos);
}

TEST(BatchManifest, JsonArrayOrItemsObject) {
  const auto dir = test::scratch_dir();
  auto items = read_batch_manifest(write(dir / "a.json", R"([{"mesh": "a.ply", "frames": 12, "seconds": 1.5}, {"mesh": "b.ply", "colour": 1}, 7])"));
  ASSERT_EQ(items.size(), 3u);
  EXPECT_EQ(items[0].values.at("frame-count"), "12");
  EXPECT_EQ(items[0].values.at("seconds"), "1.5");
  EXPECT_NE(items[1].error.find("unknown key 'colour'"), std::string::npos);
  EXPECT_NE(items[2].error.find("not a JSON object"), std::string::npos);
  items = read_batch_manifest(write(dir / "b.json", R"({"items": [{"mesh": "x/y.off", "output": "z.mp4"}]})"));
  ASSERT_EQ(items.size(), 1u);
  EXPECT_EQ(items[0].output, "z.mp4");
}

TEST(BatchManifest, NotAManifestIsAnInputError) {
  const auto dir = test::scratch_dir();
  EXPECT_THROW(read_batch_manifest(write(dir / "a.csv", "")), InputError);
  EXPECT_THROW(read_batch_manifest(write(dir / "b.csv", "mesh,colour\na,b\n")), InputError);
  EXPECT_THROW(read_batch_manifest(write(dir / "c.csv", "up,output\ny,a.mp4\n")), InputError);
  EXPECT_THROW(read_batch_manifest(write(dir / "d.csv", "mesh\n")), InputError);  // no items
  EXPECT_THROW(read_batch_manifest(write(dir / "e.json", "{\"mesh\": 1}")), InputError);
  EXPECT_THROW(read_batch_manifest(write(dir / "f.json", "[1,")), InputError);
  EXPECT_THROW(read_batch_manifest(write(dir / "g.txt", "mesh\na\n")), InputError);
  EXPECT_THROW(read_batch_manifest(dir / "missing.csv"), IoError);
}

TEST(FrameDir, PrepareWritesTheManifestOnceAndRefusesAnotherTour) {
  const auto dir = test::scratch_dir() / "frames";
  FrameDirInfo info;
  info.frame_count = 12;
  info.width = 64;
  info.height = 48;
  info.image_formats = {"png"};
  prepare_frame_dir(dir, info);
  EXPECT_EQ(read_frame_dir_info(dir).frame_count, 12);
  info.source = "another name for the same tour";
  EXPECT_NO_THROW(prepare_frame_dir(dir, info));
  info.frame_count = 13;
  try {
    prepare_frame_dir(dir, info);
    ADD_FAILURE() << "another tour was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("holds another tour (12 frames of 64x48 at 30 fps as png; this one is 13 frames"), std::string::npos)
        << e.what();
  }
  // Denoised frames do not mix with raw ones (the PNGs differ), and the manifest records which.
  info.frame_count = 12;
  info.denoise = true;
  try {
    prepare_frame_dir(dir, info);
    ADD_FAILURE() << "denoised frames were accepted into a directory of raw ones";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("this one is 12 frames of 64x48 at 30 fps as png, denoised"), std::string::npos) << e.what();
  }
  const auto denoised_dir = test::scratch_dir() / "denoised";
  prepare_frame_dir(denoised_dir, info);
  EXPECT_TRUE(read_frame_dir_info(denoised_dir).denoise);
}

TEST(BatchManifest, PosterColumnIsAPlainPngName) {
  const auto dir = test::scratch_dir();
  const auto items = read_batch_manifest(write(dir / "m.csv", "mesh,poster\na.ply,a-still.png\nb.ply,sub/b.png\nc.ply,c.jpg\n"));
  ASSERT_EQ(items.size(), 3u);
  EXPECT_EQ(items[0].error, "");
  EXPECT_EQ(items[0].values.at("poster"), "a-still.png");
  EXPECT_NE(items[1].error.find("plain file name"), std::string::npos) << items[1].error;
  EXPECT_NE(items[2].error.find(".png"), std::string::npos) << items[2].error;
}

}  // namespace
}  // namespace meshtour
