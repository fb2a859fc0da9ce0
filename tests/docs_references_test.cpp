// Every reference to the method's specification resolves: each `§N` / `§N.M` names a heading of
// docs/METHOD.md and each `I-n` one of its interpretations, so a reader who follows a comment, an
// option's help or a document lands on the text it means.
//
// The rule (which references count):
//  - `I-n` is this project's own notation (METHOD.md's "Interpretation I-n"), so every `I-n` in
//    every text file of the repository must resolve.
//  - `§` is common notation, and other documents may use it for their own sections, so a `§N`
//    counts only where it refers to METHOD.md: in docs/METHOD.md itself, docs/FIDELITY.md and
//    docs/OPTIONS.md (the generated help of every option, where the paper path's options cite
//    sections); in pathgen/ and in any file whose name starts with "pathgen" (its tests and
//    benchmark); in the `path` command (cli/path_*); and in any file that names METHOD.md. A file
//    that needs § for another document must not name METHOD.md (or must cite it by I-n only).
//  - Targets: a heading "## N. Title" or "### N.M Title" (any depth, "N.M.K" too) defines §N,
//    §N.M, ...; a paragraph starting "> **Interpretation I-n" defines I-n.
//  - Text files are sources, scripts, CMake files and documents (not JSON: data, and lock files
//    whose base64 hashes hold runs like "I-" and a digit); .git, build trees (any folder holding a
//    CMakeCache.txt), node_modules, fuzz corpora and golden images are skipped.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "helpers.h"

namespace {

namespace fs = std::filesystem;

// Spelled by its UTF-8 bytes, so that the synthetic references below are not references of this
// file (it names METHOD.md, so its own § count).
const std::string kSectionSign = "\xc2\xa7";

/// The sections (as "7", "7.3") and interpretation numbers METHOD.md defines.
struct MethodTargets {
  std::set<std::string> sections;
  std::set<int> interpretations;
};

MethodTargets targets_of(const std::string& method_text) {
  MethodTargets t;
  static const std::regex heading(R"(^#{2,6}[ \t]+(\d+(?:\.\d+)*)\.?[ \t])");
  static const std::regex interpretation(R"(^>[ \t]*\*\*Interpretation I-(\d+)\b)");
  std::istringstream lines(method_text);
  std::string line;
  bool in_code = false;
  while (std::getline(lines, line)) {
    if (line.rfind("```", 0) == 0) in_code = !in_code;
    if (in_code) continue;
    std::smatch m;
    if (std::regex_search(line, m, heading)) t.sections.insert(m[1].str());
    if (std::regex_search(line, m, interpretation)) t.interpretations.insert(std::stoi(m[1].str()));
  }
  return t;
}

/// One reference that does not resolve, for the failure message.
struct Unresolved {
  std::string where;  ///< file:line
  std::string reference;
};

/// The references of `text` (from `file`) that METHOD.md does not define. `sections_count` says
/// whether § references in this text refer to METHOD.md (see the rule above); `checked` counts
/// every reference looked at.
std::vector<Unresolved> unresolved_in(const std::string& text, const std::string& file, bool sections_count,
                                      const MethodTargets& targets, int& checked) {
  static const std::regex section(kSectionSign + R"(\s?(\d+(?:\.\d+)*))");
  static const std::regex interpretation(R"(\bI-(\d+)\b)");
  std::vector<Unresolved> bad;
  std::istringstream lines(text);
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    const std::string where = file + ":" + std::to_string(number);
    if (sections_count) {
      if (line.find(kSectionSign) != std::string::npos)
        for (auto it = std::sregex_iterator(line.begin(), line.end(), section); it != std::sregex_iterator(); ++it) {
          ++checked;
          const std::string id = (*it)[1].str();
          if (!targets.sections.count(id)) bad.push_back({where, kSectionSign + id});
        }
    }
    if (line.find("I-") == std::string::npos) continue;
    for (auto it = std::sregex_iterator(line.begin(), line.end(), interpretation); it != std::sregex_iterator();
         ++it) {
      ++checked;
      if (!targets.interpretations.count(std::stoi((*it)[1].str()))) bad.push_back({where, "I-" + (*it)[1].str()});
    }
  }
  return bad;
}

bool is_text_file(const fs::path& file) {
  static const std::set<std::string> extensions = {".h", ".hpp", ".cpp", ".cc", ".c", ".in", ".md",
                                                    ".txt", ".sh", ".js", ".py", ".cmake"};
  const std::string name = file.filename().string();
  return name == "CMakeLists.txt" || extensions.count(file.extension().string()) > 0 || name == "run";
}

bool skipped_directory(const fs::path& dir, const fs::path& root) {
  const std::string name = dir.filename().string();
  const std::string relative = fs::relative(dir, root).generic_string();
  return name == ".git" || name == "node_modules" || relative == "fuzz/corpus" || relative == "golden_images" ||
         fs::exists(dir / "CMakeCache.txt");
}

/// Whether the § references of `relative` (a path from the repository root) refer to METHOD.md.
bool sections_refer_to_method(const std::string& relative, const std::string& text) {
  if (relative == "docs/METHOD.md" || relative == "docs/FIDELITY.md" || relative == "docs/OPTIONS.md") return true;
  if (relative.rfind("pathgen/", 0) == 0 || relative.rfind("cli/path_", 0) == 0) return true;
  if (fs::path(relative).filename().string().rfind("pathgen", 0) == 0) return true;
  return text.find("METHOD.md") != std::string::npos;
}

std::string report(const std::vector<Unresolved>& bad) {
  std::string s;
  for (const auto& b : bad) s += "  " + b.where + ": " + b.reference + "\n";
  return s;
}

TEST(DocsReferences, MethodDefinesItsSectionsAndInterpretations) {
  const MethodTargets t = targets_of(meshtour::test::file_bytes(meshtour::test::source_dir() / "docs/METHOD.md"));
  for (int n = 1; n <= 19; ++n) EXPECT_TRUE(t.sections.count(std::to_string(n))) << "§" << n << " has no heading";
  EXPECT_TRUE(t.sections.count("7.3"));
  EXPECT_TRUE(t.sections.count("19.2"));
  // The interpretations are numbered without gaps, so a stale ID cannot hide in one.
  ASSERT_FALSE(t.interpretations.empty());
  EXPECT_EQ(*t.interpretations.begin(), 1);
  EXPECT_EQ(static_cast<int>(t.interpretations.size()), *t.interpretations.rbegin())
      << "the interpretation IDs have a gap";
}

TEST(DocsReferences, AnUnknownSectionOrInterpretationIsReported) {
  const std::string S = kSectionSign;
  const MethodTargets t = targets_of(
      "## 7. Patches\n### 7.3 Phase A\n```\n## 8. not a heading inside code\n```\n"
      "> **Interpretation I-" "2 — something.** text\n");
  EXPECT_EQ(t.sections, (std::set<std::string>{"7", "7.3"}));
  EXPECT_EQ(t.interpretations, (std::set<int>{2}));
  int checked = 0;
  const std::string text = "see " + S + "7.3 and " + S + "7, I-" "2.\nbut " + S + "8, " + S + "7.4 and I-" "3\n";
  const auto bad = unresolved_in(text, "x.h", true, t, checked);
  EXPECT_EQ(checked, 6);
  ASSERT_EQ(bad.size(), 3u) << report(bad);
  EXPECT_EQ(bad[0].where, "x.h:2");
  EXPECT_EQ(bad[0].reference, S + "8");
  EXPECT_EQ(bad[1].reference, S + "7.4");
  EXPECT_EQ(bad[2].reference, "I-" "3");
  // Where § refers to another document, only I-n counts.
  EXPECT_TRUE(unresolved_in("Debian Policy " + S + "4.9, I-" "2", "y.md", false, t, checked).empty());
  EXPECT_EQ(unresolved_in("Debian Policy " + S + "4.9, I-" "2", "y.md", true, t, checked).size(), 1u);
}

TEST(DocsReferences, EveryReferenceInTheRepositoryResolves) {
  const fs::path root = meshtour::test::source_dir();
  const MethodTargets targets = targets_of(meshtour::test::file_bytes(root / "docs/METHOD.md"));
  ASSERT_FALSE(targets.sections.empty()) << "no headings read from " << (root / "docs/METHOD.md");
  std::vector<Unresolved> bad;
  int checked = 0;
  int files = 0;
  for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator(); ++it) {
    if (it->is_directory()) {
      if (skipped_directory(it->path(), root)) it.disable_recursion_pending();
      continue;
    }
    if (!it->is_regular_file() || !is_text_file(it->path())) continue;
    const std::string relative = fs::relative(it->path(), root).generic_string();
    const std::string text = meshtour::test::file_bytes(it->path());
    ++files;
    const auto found = unresolved_in(text, relative, sections_refer_to_method(relative, text), targets, checked);
    bad.insert(bad.end(), found.begin(), found.end());
  }
  RecordProperty("files", files);
  RecordProperty("references", checked);
  // The tree cites METHOD.md a few hundred times; far fewer means the walk missed the sources.
  EXPECT_GT(files, 100);
  EXPECT_GT(checked, 300) << "only " << checked << " references found in " << files << " files";
  EXPECT_TRUE(bad.empty()) << bad.size() << " references do not resolve to a heading or an interpretation of "
                           << "docs/METHOD.md (see the rule at the top of tests/docs_references_test.cpp):\n"
                           << report(bad);
}

}  // namespace
