// The folders' layering, as docs/ARCHITECTURE.md draws it: each folder includes only the
// folders of the table below (its "#include "folder/..." lines), and the folders form no cycle.
// Data flows one way (mesh -> pathgen -> camera path -> tracer -> frames -> encoder); option text
// is parsed at the edge (cli/, and the scene-file and manifest readers in scenes/ and options/),
// so the libraries below never see it: no library folder includes options/.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>

#include "helpers.h"

namespace {

namespace fs = std::filesystem;

using Folders = std::set<std::string>;

// What each folder may include, besides itself. Keep docs/ARCHITECTURE.md's diagram in step.
const std::map<std::string, Folders>& allowed() {
  static const std::map<std::string, Folders> table = {
      {"core", {}},
      {"mesh", {"core"}},
      {"visibility", {"core", "mesh"}},
      {"pathgen", {"core", "mesh", "visibility"}},
      {"tracer", {"core", "mesh"}},
      {"encoder", {"core"}},
      {"jobs", {"core"}},
      {"evaluate", {"core", "mesh", "visibility", "pathgen"}},
      // The edge: the registry and the manifest reader parse text into the libraries' settings.
      {"options", {"core", "mesh", "visibility", "pathgen", "tracer", "encoder", "jobs"}},
      {"scenes", {"core", "mesh", "visibility", "pathgen", "tracer", "encoder", "jobs", "options"}},
      // The tour library takes typed settings: it includes no options/ and no cli/.
      {"tour", {"core", "mesh", "visibility", "pathgen", "tracer", "encoder", "jobs", "evaluate", "scenes"}},
      {"cli", {"core", "mesh", "visibility", "pathgen", "tracer", "encoder", "jobs", "evaluate", "options", "scenes", "tour"}},
  };
  return table;
}

/// folder -> the other project folders its sources include.
std::map<std::string, Folders> includes_by_folder(const fs::path& root) {
  static const std::regex include(R"(^\s*#\s*include\s+"([a-z_]+)/)");
  std::map<std::string, Folders> found;
  for (const auto& [folder, unused] : allowed()) {
    found[folder];
    for (const auto& entry : fs::recursive_directory_iterator(root / folder)) {
      const std::string ext = entry.path().extension().string();
      if (!entry.is_regular_file() || (ext != ".h" && ext != ".cpp" && ext != ".in")) continue;
      std::ifstream in(entry.path());
      std::string line;
      std::smatch m;
      while (std::getline(in, line))
        if (std::regex_search(line, m, include) && m[1].str() != folder && allowed().count(m[1].str()))
          found[folder].insert(m[1].str());
    }
  }
  return found;
}

bool reaches(const std::map<std::string, Folders>& graph, const std::string& from, const std::string& to,
             Folders& seen) {
  for (const std::string& next : graph.at(from)) {
    if (next == to) return true;
    if (seen.insert(next).second && reaches(graph, next, to, seen)) return true;
  }
  return false;
}

TEST(Layering, EachFolderIncludesOnlyTheFoldersBelowIt) {
  const auto found = includes_by_folder(meshtour::test::source_dir());
  for (const auto& [folder, used] : found)
    for (const std::string& other : used)
      EXPECT_TRUE(allowed().at(folder).count(other))
          << folder << "/ includes " << other << "/, against the layering of docs/ARCHITECTURE.md";
}

TEST(Layering, NoLibraryBelowTheEdgeReadsOptionText) {
  const auto found = includes_by_folder(meshtour::test::source_dir());
  for (const char* library : {"mesh", "visibility", "pathgen", "tracer", "encoder", "jobs", "evaluate", "tour"})
    EXPECT_FALSE(found.at(library).count("options")) << library << "/ includes options/";
}

TEST(Layering, FoldersFormNoCycle) {
  const auto found = includes_by_folder(meshtour::test::source_dir());
  for (const auto& [folder, unused] : found) {
    Folders seen;
    EXPECT_FALSE(reaches(found, folder, folder, seen)) << folder << "/ reaches itself through its includes";
  }
}

// The checks can fail: a made-up graph with a cycle is found, and a wrong arrow is seen.
TEST(Layering, ACycleIsFound) {
  std::map<std::string, Folders> graph = {{"a", {"b"}}, {"b", {"c"}}, {"c", {"a"}}, {"d", {"a"}}};
  Folders seen;
  EXPECT_TRUE(reaches(graph, "a", "a", seen));
  seen.clear();
  EXPECT_FALSE(reaches(graph, "d", "d", seen));
}

}  // namespace
