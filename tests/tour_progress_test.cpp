// Progress output (tour/progress.h) in each mode: the JSON lines a log collector parses, the
// terminal bar and its summary, and silence.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <sstream>
#include <string>
#include <vector>

#include "tour/progress.h"

namespace {

using namespace meshtour;
using testing::internal::CaptureStderr;
using testing::internal::GetCapturedStderr;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(TourProgress, JsonModeWritesOneParsableLinePerStepAndASummary) {
  CaptureStderr();
  {
    Progress progress("frame", 4, ProgressMode::json);
    progress.step_done(12, 0.25, 1);
    progress.step_done(13, 0.5, 2);
    progress.update(3);
    progress.finish(1);
  }
  const std::vector<std::string> lines = lines_of(GetCapturedStderr());
  ASSERT_EQ(lines.size(), 4u);
  std::vector<nlohmann::json> events;
  for (const auto& line : lines) {
    ASSERT_NO_THROW(events.push_back(nlohmann::json::parse(line))) << line;
  }
  // A finished step names its index under the step's own name, with its time and the count done.
  EXPECT_EQ(events[0]["event"], "frame");
  EXPECT_EQ(events[0]["frame"], 12);
  EXPECT_DOUBLE_EQ(events[0]["seconds"].get<double>(), 0.25);
  EXPECT_EQ(events[0]["done"], 1);
  EXPECT_EQ(events[0]["total"], 4);
  EXPECT_EQ(events[1]["frame"], 13);
  EXPECT_EQ(events[1]["done"], 2);
  // A plain update has no index, only the count.
  EXPECT_EQ(events[2]["event"], "frame");
  EXPECT_EQ(events[2]["done"], 3);
  EXPECT_FALSE(events[2].contains("frame"));
  EXPECT_GE(events[2]["elapsed"].get<double>(), 0.0);
  // The summary counts the last update and the steps that were already done.
  EXPECT_EQ(events[3]["event"], "summary");
  EXPECT_EQ(events[3]["what"], "frame");
  EXPECT_EQ(events[3]["done"], 3);
  EXPECT_EQ(events[3]["total"], 4);
  EXPECT_EQ(events[3]["skipped"], 1);
  EXPECT_GE(events[3]["seconds"].get<double>(), 0.0);
  EXPECT_TRUE(events[3].contains("per_second"));
}

TEST(TourProgress, AutomaticModeAwayFromATerminalWritesJsonLines) {
  // While captured, stderr is a file, as in a farm or batch log.
  CaptureStderr();
  {
    Progress progress("chunk", 2, ProgressMode::automatic);
    progress.step_done(0, 1.0, 1);
    progress.finish();
  }
  const std::vector<std::string> lines = lines_of(GetCapturedStderr());
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(nlohmann::json::parse(lines[0])["chunk"], 0);
  EXPECT_EQ(nlohmann::json::parse(lines[1])["event"], "summary");
}

TEST(TourProgress, BarModeRedrawsOneLineAndEndsWithASummary) {
  CaptureStderr();
  {
    Progress progress("frame", 4, ProgressMode::bar);
    progress.update(1);
    progress.step_done(7, 0.1, 2);
    progress.finish(3);
  }
  const std::string out = GetCapturedStderr();
  // Each redraw starts with a carriage return, so the terminal shows one line.
  EXPECT_EQ(out.rfind('\r', 0), 0u) << out;
  EXPECT_NE(out.find("\r[#######.......................] 1/4 frames"), std::string::npos) << out;
  EXPECT_NE(out.find("\r[###############...............] 2/4 frames"), std::string::npos) << out;
  EXPECT_EQ(out.find('{'), std::string::npos) << "no JSON in bar mode: " << out;
  const std::vector<std::string> lines = lines_of(out);
  ASSERT_EQ(lines.size(), 2u) << out;
  EXPECT_EQ(lines[1].rfind("frames: 2 done in ", 0), 0u) << lines[1];
  EXPECT_NE(lines[1].find(", 3 already there"), std::string::npos) << lines[1];
}

TEST(TourProgress, NoneModeIsSilent) {
  CaptureStderr();
  {
    Progress progress("frame", 3, ProgressMode::none);
    progress.update(1);
    progress.step_done(1, 0.5, 2);
    progress.finish(1);
  }
  EXPECT_EQ(GetCapturedStderr(), "");
}

}  // namespace
