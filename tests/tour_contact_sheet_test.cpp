// The contact sheet of a batch (tour/contact_sheet.h): the page's content from its items (counts,
// escaping, links, failed items), the same bytes for the same items, and the page written from
// one batch summary or from a farm's summaries, one per array task.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "helpers.h"
#include "tour/contact_sheet.h"

namespace {

using namespace meshtour;
namespace fs = std::filesystem;

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

std::vector<SheetItem> two_items() {
  SheetItem done;
  done.index = 0;
  done.name = "bunny.ply";
  done.caption = "Bunny <scan> & \"friends\"";
  done.status = "done";
  done.video = "my tour.mp4";
  done.webm = "my tour.webm";
  done.poster = "poster 0.png";
  done.gltf = "camera.gltf";
  done.faces = 69451;
  done.seconds = 4.0;
  SheetItem failed;
  failed.index = 1;
  failed.name = "broken.obj";
  failed.status = "failed";
  failed.error = "broken.obj: line 3: a face needs three corners\nsecond line of the message";
  failed.video = "broken.mp4";  // written by no one: a failed item links nothing
  return {done, failed};
}

TEST(TourContactSheet, PageShowsEveryItemWithItsStatusAndEscapedText) {
  const std::string html = contact_sheet_html("batch <1>", two_items(), {"batch-summary.json"});
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(html.find("<title>batch &lt;1&gt;</title>"), std::string::npos);
  EXPECT_NE(html.find("2 items, 1 done, 1 failed."), std::string::npos);
  EXPECT_NE(html.find("<a href=\"batch-summary.json\">batch-summary.json</a>"), std::string::npos);

  // The done item: its video (both codecs, the WebM first), poster, links, faces and duration.
  EXPECT_NE(html.find("id=\"item-0\" data-status=\"done\""), std::string::npos);
  EXPECT_NE(html.find("Bunny &lt;scan&gt; &amp; &quot;friends&quot;"), std::string::npos);
  EXPECT_EQ(html.find("<scan>"), std::string::npos) << "caption text must be escaped";
  EXPECT_NE(html.find("poster=\"poster%200.png\""), std::string::npos) << "file names are percent-encoded in links";
  EXPECT_LT(html.find("<source src=\"my%20tour.webm\" type=\"video/webm\">"),
            html.find("<source src=\"my%20tour.mp4\" type=\"video/mp4\">"));
  EXPECT_NE(html.find("69451 faces"), std::string::npos);
  EXPECT_NE(html.find("4.0 s"), std::string::npos);
  EXPECT_NE(html.find("<a href=\"camera.gltf\">glTF camera</a>"), std::string::npos);

  // The failed item: no video and no links, only the first line of its error.
  EXPECT_NE(html.find("id=\"item-1\" data-status=\"failed\""), std::string::npos);
  EXPECT_NE(html.find("<div class=\"error\">broken.obj: line 3: a face needs three corners</div>"), std::string::npos);
  EXPECT_EQ(html.find("second line of the message"), std::string::npos);
  EXPECT_EQ(html.find("broken.mp4"), std::string::npos);
  EXPECT_EQ(count_of(html, "<video "), 1u);
  EXPECT_EQ(count_of(html, "no video"), 1u);
}

TEST(TourContactSheet, SameItemsGiveTheSameBytes) {
  const auto items = two_items();
  EXPECT_EQ(contact_sheet_html("t", items, {"a.json"}), contact_sheet_html("t", items, {"a.json"}));
  auto changed = items;
  changed[0].faces = 69452;
  EXPECT_NE(contact_sheet_html("t", items, {"a.json"}), contact_sheet_html("t", changed, {"a.json"}));
  // No items: an empty grid, still a page.
  const std::string empty = contact_sheet_html("t", {}, {});
  EXPECT_NE(empty.find("0 items, 0 done, 0 failed."), std::string::npos);
  EXPECT_EQ(count_of(empty, "class=\"item\""), 0u);
}

void write_summary(const fs::path& file, const std::vector<nlohmann::json>& items) {
  nlohmann::json j;
  j["items"] = items;
  std::ofstream(file) << j.dump(2);
}

nlohmann::json summary_item(int index, const std::string& mesh, const std::string& status) {
  nlohmann::json i = {{"index", index}, {"mesh", "/data/meshes/" + mesh}, {"status", status}};
  if (status == "done") {
    i["output"] = "item" + std::to_string(index) + ".mp4";
    i["faces"] = 100 + index;
    i["duration"] = 2.5;
  } else {
    i["error"] = mesh + ": cannot be read";
  }
  return i;
}

TEST(TourContactSheet, WrittenFromOneSummaryOrFromAFarmsSummariesInItemOrder) {
  const fs::path dir = test::scratch_dir();
  // No summary yet: refused with what to do.
  try {
    write_contact_sheet(dir);
    FAIL() << "a folder without summaries was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("run the batch first"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "index.html"));

  // A farm: one summary per array task, found in any order, items sorted by index.
  write_summary(dir / "batch-summary-2.json", {summary_item(2, "c.ply", "done")});
  write_summary(dir / "batch-summary-0.json", {summary_item(0, "a.ply", "done")});
  write_summary(dir / "batch-summary-1.json", {summary_item(1, "b.obj", "failed")});
  const fs::path page = write_contact_sheet(dir);
  EXPECT_EQ(page, dir / "index.html");
  const std::string farm = test::file_bytes(page);
  EXPECT_NE(farm.find("3 items, 2 done, 1 failed."), std::string::npos);
  const auto a = farm.find("id=\"item-0\""), b = farm.find("id=\"item-1\""), c = farm.find("id=\"item-2\"");
  ASSERT_NE(c, std::string::npos);
  EXPECT_LT(a, b);
  EXPECT_LT(b, c);
  // Only the mesh's file name is shown, never the folder it came from.
  EXPECT_NE(farm.find(">a.ply &middot; 100 faces &middot; 2.5 s"), std::string::npos);
  EXPECT_EQ(farm.find("/data/meshes"), std::string::npos);
  // The summaries are linked in name order.
  EXPECT_NE(farm.find("<a href=\"batch-summary-0.json\">batch-summary-0.json</a> <a href=\"batch-summary-1.json\">"),
            std::string::npos);

  // A single run's summary takes precedence over the per-task ones.
  write_summary(dir / "batch-summary.json", {summary_item(0, "only.ply", "done")});
  const std::string single = test::file_bytes(write_contact_sheet(dir));
  EXPECT_NE(single.find("1 items, 1 done, 0 failed."), std::string::npos);
  EXPECT_EQ(single.find("batch-summary-0.json"), std::string::npos);

  // A damaged summary is named.
  std::ofstream(dir / "batch-summary.json") << "{ not json";
  try {
    write_contact_sheet(dir);
    FAIL() << "a damaged summary was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("batch-summary.json: not a batch summary"), std::string::npos) << e.what();
  }
}

}  // namespace
