// docs/OPTIONS.md lists every flag of every command: the flags `meshtour <command> --help` shows
// and the ones the document lists for that command are the same set, both ways.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include "helpers.h"

namespace meshtour {
namespace {

// The flags of CLI11's help: the option lines start with two blanks and a dash ("  -o,--output
// FILE  ..."); wrapped descriptions are indented further.
std::set<std::string> help_flags(const std::string& help) {
  std::set<std::string> flags;
  std::istringstream in(help);
  for (std::string line; std::getline(in, line);) {
    if (line.size() < 3 || line.compare(0, 3, "  -") != 0) continue;
    std::string names = line.substr(2, line.find(' ', 2) - 2);
    std::istringstream parts(names);
    for (std::string name; std::getline(parts, name, ',');)
      if (name != "-h" && name != "--help") flags.insert(name);
  }
  return flags;
}

// The document's list per command: lines "- `meshtour <command>`: `--a`, `-o` `--output`, ...".
std::map<std::string, std::set<std::string>> doc_flags(const std::string& doc) {
  std::map<std::string, std::set<std::string>> by_command;
  std::istringstream in(doc);
  const std::string prefix = "- `meshtour ";
  for (std::string line; std::getline(in, line);) {
    if (line.compare(0, prefix.size(), prefix) != 0) continue;
    const std::size_t end = line.find('`', prefix.size());
    std::set<std::string>& flags = by_command[line.substr(prefix.size(), end - prefix.size())];
    for (std::size_t open = line.find("`-", end); open != std::string::npos; open = line.find("`-", open + 1)) {
      const std::size_t close = line.find('`', open + 1);
      flags.insert(line.substr(open + 1, close - open - 1));
      open = close;
    }
  }
  return by_command;
}

std::string list(const std::set<std::string>& flags) {
  std::string text;
  for (const auto& f : flags) text += (text.empty() ? "" : " ") + f;
  return text.empty() ? "(none)" : text;
}

TEST(OptionsDoc, ListsEveryFlagOfEveryCommand) {
  std::ifstream in(test::source_dir() / "docs" / "OPTIONS.md", std::ios::binary);
  std::stringstream doc;
  doc << in.rdbuf();
  const auto documented = doc_flags(doc.str());
  const char* const commands[] = {"tour", "render", "batch", "farm slurm", "path", "evaluate", "encode", "info"};
  EXPECT_EQ(documented.size(), std::size(commands)) << "docs/OPTIONS.md lists flags for other commands than meshtour has";
  for (const std::string command : commands) {
    const auto r = test::run_meshtour(command + " --help");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::set<std::string> shown = help_flags(r.output);
    ASSERT_FALSE(shown.empty()) << command << " --help shows no flags:\n" << r.output;
    const auto it = documented.find(command);
    ASSERT_NE(it, documented.end()) << "docs/OPTIONS.md has no list of the flags of " << command;
    std::set<std::string> undocumented, not_shown;
    for (const auto& f : shown)
      if (!it->second.contains(f)) undocumented.insert(f);
    for (const auto& f : it->second)
      if (!shown.contains(f)) not_shown.insert(f);
    EXPECT_TRUE(undocumented.empty()) << command << ": in --help but not in docs/OPTIONS.md: " << list(undocumented);
    EXPECT_TRUE(not_shown.empty()) << command << ": in docs/OPTIONS.md but not in --help: " << list(not_shown);
  }
}

}  // namespace
}  // namespace meshtour
