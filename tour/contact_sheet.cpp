#include "tour/contact_sheet.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>

#include "core/atomic_file.h"
#include "core/error.h"

namespace meshtour {
namespace {

namespace fs = std::filesystem;

// Text and attribute values: the five characters HTML gives a meaning.
std::string escape(std::string_view text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

// A relative link to a file name: percent-encodes what is not safe in a URL path segment.
std::string href(std::string_view file) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  for (const unsigned char c : file) {
    if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~') out += static_cast<char>(c);
    else (out += '%') += hex[c >> 4], out += hex[c & 15];
  }
  return escape(out);
}

std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

constexpr const char* kStyle = R"(body{font-family:system-ui,sans-serif;margin:1.5rem;background:#f4f4f2;color:#222}
h1{font-size:1.4rem;margin:0 0 .3rem}p.summary{margin:0 0 1.2rem;color:#555}
.grid{display:grid;grid-template-columns:repeat(auto-fill,minmax(300px,1fr));gap:1rem}
.item{background:#fff;border-radius:6px;box-shadow:0 1px 3px #0002;overflow:hidden}
.item video,.item .missing{display:block;width:100%;aspect-ratio:16/9;background:#222;object-fit:contain;cursor:pointer}
.item .missing{display:flex;align-items:center;justify-content:center;color:#eee;font-size:.9rem}
.meta{padding:.6rem .8rem;font-size:.85rem;line-height:1.4}.caption{font-weight:600;font-size:.95rem}
.status{display:inline-block;padding:0 .4rem;border-radius:3px;color:#fff;font-size:.75rem}
.done{background:#2a7d3c}.failed{background:#b3261e}.error{color:#b3261e;word-break:break-word}
.links a{margin-right:.6rem})";

// Plays a video on hover or click and stops it when the pointer leaves.
constexpr const char* kScript = R"(for (const v of document.querySelectorAll('video')) {
  v.addEventListener('mouseenter', () => v.play().catch(() => {}));
  v.addEventListener('mouseleave', () => v.pause());
  v.addEventListener('click', () => (v.paused ? v.play().catch(() => {}) : v.pause()));
})";

std::string format_seconds(double s) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f s", s);
  return text;
}

std::vector<SheetItem> read_summary(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw InputError(file.string() + ": not a batch summary: " + e.what());
  }
  std::vector<SheetItem> items;
  for (const auto& i : j.value("items", nlohmann::json::array())) {
    SheetItem s;
    s.index = i.value("index", 0);
    s.name = fs::path(i.value("mesh", std::string())).filename().string();
    s.caption = i.value("caption", std::string());
    s.status = i.value("status", std::string());
    s.error = i.value("error", std::string());
    s.exit_class = i.value("exit_class", std::string());
    s.video = i.value("output", std::string());
    s.webm = i.value("webm", std::string());
    s.poster = i.value("poster", std::string());
    s.gltf = i.value("gltf", std::string());
    s.faces = i.value("faces", -1LL);
    s.seconds = i.value("duration", -1.0);
    items.push_back(std::move(s));
  }
  return items;
}

}  // namespace

std::string contact_sheet_html(const std::string& title, const std::vector<SheetItem>& items,
                               const std::vector<std::string>& summary_files) {
  const auto failed = std::count_if(items.begin(), items.end(), [](const SheetItem& i) { return i.status == "failed"; });
  std::string h = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                  "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>" + escape(title) +
                  "</title>\n<style>\n" + kStyle + "\n</style>\n</head>\n<body>\n<h1>" + escape(title) + "</h1>\n" +
                  "<p class=\"summary\">" + std::to_string(items.size()) + " items, " +
                  std::to_string(static_cast<long>(items.size()) - failed) + " done, " + std::to_string(failed) +
                  " failed. Hover or click a poster to play its video. Summary:";
  for (const auto& f : summary_files) h += " <a href=\"" + href(f) + "\">" + escape(f) + "</a>";
  h += "</p>\n<div class=\"grid\">\n";
  for (const auto& i : items) {
    const bool done = i.status != "failed";
    h += "<div class=\"item\" id=\"item-" + std::to_string(i.index) + "\" data-status=\"" + (done ? "done" : "failed") + "\">\n";
    if (done && !i.video.empty()) {
      h += "<video muted playsinline loop preload=\"none\"";
      if (!i.poster.empty()) h += " poster=\"" + href(i.poster) + "\"";
      h += ">";
      if (!i.webm.empty()) h += "<source src=\"" + href(i.webm) + "\" type=\"video/webm\">";
      h += "<source src=\"" + href(i.video) + "\" type=\"video/mp4\"></video>\n";
      // The poster also as an image the page (and its test) can check was loaded.
      if (!i.poster.empty()) h += "<img class=\"poster\" hidden alt=\"\" src=\"" + href(i.poster) + "\">\n";
    } else {
      h += "<div class=\"missing\">no video</div>\n";
    }
    h += "<div class=\"meta\">\n<div class=\"caption\">" + escape(i.caption.empty() ? i.name : i.caption) + "</div>\n";
    h += "<div>" + escape(i.name);
    if (i.faces >= 0) h += " &middot; " + std::to_string(i.faces) + " faces";
    if (i.seconds >= 0) h += " &middot; " + format_seconds(i.seconds);
    h += std::string(" &middot; <span class=\"status ") + (done ? "done\">done" : "failed\">failed") + "</span></div>\n";
    if (!done)
      h += "<div class=\"error\">" + (i.exit_class.empty() ? std::string() : escape(i.exit_class) + " error: ") +
           escape(first_line(i.error)) + "</div>\n";
    h += "<div class=\"links\">";
    const auto link = [&](const std::string& file, const char* label) {
      if (!file.empty() && done) h += "<a href=\"" + href(file) + "\">" + label + "</a>";
    };
    link(i.video, "MP4");
    link(i.webm, "WebM");
    link(i.poster, "poster");
    link(i.gltf, "glTF camera");
    h += "</div>\n</div>\n</div>\n";
  }
  h += "</div>\n<script>\n" + std::string(kScript) + "\n</script>\n</body>\n</html>\n";
  return h;
}

fs::path write_contact_sheet(const fs::path& out_dir) {
  std::vector<std::string> files;
  if (fs::exists(out_dir / "batch-summary.json")) {
    files.push_back("batch-summary.json");
  } else {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(out_dir, ec)) {
      const std::string name = e.path().filename().string();
      if (name.starts_with("batch-summary-") && name.ends_with(".json")) files.push_back(name);
    }
  }
  if (files.empty())
    throw InputError(out_dir.string() + ": no batch-summary.json or batch-summary-<item>.json; run the batch first");
  std::vector<SheetItem> items;
  for (const auto& f : files) {
    auto part = read_summary(out_dir / f);
    items.insert(items.end(), part.begin(), part.end());
  }
  std::sort(items.begin(), items.end(), [](const SheetItem& a, const SheetItem& b) { return a.index < b.index; });
  std::sort(files.begin(), files.end());
  const fs::path page = out_dir / "index.html";
  write_text_file_atomically(page, contact_sheet_html("meshtour batch: " + fs::absolute(out_dir).filename().string(), items, files),
                             "contact sheet");
  return page;
}

}  // namespace meshtour
