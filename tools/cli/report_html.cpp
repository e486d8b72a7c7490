// The self-contained report page (tools/cli/report_html.h).
#include "tools/cli/report_html.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"

#include <sstream>

namespace iblx::cli {
namespace {

// Sorting, and a status the tests read: data-status on <html> becomes "ok" once every image has decoded, or
// says what went wrong (a script error, images that did not load).
// In <head>, before any other script, so that an error anywhere on the page is caught.
constexpr const char* kErrorScript =
    "window.addEventListener('error', e => { document.documentElement.dataset.status = 'script error: ' + "
    "e.message; });";
constexpr const char* kScript = R"(
function sortKey(cell) {
  const n = parseFloat(cell.textContent);
  return Number.isNaN(n) ? cell.textContent.toLowerCase() : n;
}
function sortBy(th) {
  const table = th.closest('table'), column = th.cellIndex, body = table.tBodies[0];
  const ascending = th.dataset.order !== 'ascending';
  table.querySelectorAll('th').forEach(h => delete h.dataset.order);
  th.dataset.order = ascending ? 'ascending' : 'descending';
  const rows = Array.from(body.rows);
  rows.sort((a, b) => {
    const x = sortKey(a.cells[column]), y = sortKey(b.cells[column]);
    if (typeof x !== typeof y) return typeof x === 'number' ? -1 : 1;  // numbers before dashes and words
    return (x < y ? -1 : x > y ? 1 : 0) * (ascending ? 1 : -1);
  });
  rows.forEach(r => body.appendChild(r));
}
document.querySelectorAll('table.sortable th').forEach(th => th.addEventListener('click', () => sortBy(th)));
window.addEventListener('load', () => {
  const root = document.documentElement;
  if (root.dataset.status && root.dataset.status.startsWith('script error')) return;
  const broken = Array.from(document.images).filter(i => !i.complete || i.naturalWidth === 0);
  root.dataset.status = broken.length ? 'missing images: ' + broken.map(i => i.alt).join(', ') : 'ok';
});
)";

constexpr const char* kStyle = R"(
body { font: 14px/1.45 system-ui, sans-serif; margin: 24px; color: #222; background: #fafafa; }
h1 { font-size: 22px; } h2 { font-size: 18px; margin-top: 28px; } h3 { font-size: 16px; }
table { border-collapse: collapse; margin: 8px 0; background: #fff; }
th, td { border: 1px solid #ccc; padding: 3px 8px; white-space: nowrap; }
th { background: #eee; cursor: pointer; user-select: none; }
th[data-order=ascending]::after { content: ' \25B2'; } th[data-order=descending]::after { content: ' \25BC'; }
td.number { text-align: right; font-variant-numeric: tabular-nums; }
.wide { overflow-x: auto; }
.figures { display: flex; flex-wrap: wrap; gap: 14px; }
figure { margin: 0; background: #fff; border: 1px solid #ddd; padding: 6px; }
figure img { display: block; image-rendering: pixelated; }
figcaption { font-size: 12px; max-width: 100%; word-break: break-all; }
)";

constexpr char kPlaceholder = '\x01';  // stands for the next image's data URI in blocks_

}  // namespace

std::string base64(const std::vector<unsigned char>& bytes) {
  static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::uint32_t n = std::uint32_t(bytes[i]) << 16 |
                            (i + 1 < bytes.size() ? std::uint32_t(bytes[i + 1]) << 8 : 0u) |
                            (i + 2 < bytes.size() ? std::uint32_t(bytes[i + 2]) : 0u);
    out += kDigits[n >> 18 & 63];
    out += kDigits[n >> 12 & 63];
    out += i + 1 < bytes.size() ? kDigits[n >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? kDigits[n & 63] : '=';
  }
  return out;
}

std::string htmlEscape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

HtmlReport::HtmlReport(std::string title) : title_(std::move(title)) {}

void HtmlReport::heading(const std::string& text, int level) {
  std::string tag = "h";
  tag += std::to_string(level);
  std::string block = "<";  // appended piecewise: GCC 12 warns falsely (-Wrestrict) on a chain of string +
  block.append(tag).append(">").append(htmlEscape(text)).append("</").append(tag).append(">");
  blocks_.push_back(std::move(block));
}

void HtmlReport::paragraph(const std::string& text) {
  blocks_.push_back("<p>" + htmlEscape(text) + "</p>");
}

void HtmlReport::table(const TextTable& table) {
  std::ostringstream s;
  s << "<div class=\"wide\"><table class=\"sortable\"><thead><tr>";
  for (const auto& h : table.headers) s << "<th title=\"sort\">" << htmlEscape(h) << "</th>";
  s << "</tr></thead><tbody>";
  for (const auto& row : table.rows) {
    s << "<tr>";
    for (std::size_t c = 0; c < row.size(); ++c) {
      const bool number = c < table.rightAligned.size() && table.rightAligned[c];
      s << (number ? "<td class=\"number\">" : "<td>") << htmlEscape(row[c]) << "</td>";
    }
    s << "</tr>";
  }
  s << "</tbody></table></div>";
  blocks_.push_back(s.str());
}

void HtmlReport::figures(const std::vector<Figure>& figures, int displayWidth) {
  std::ostringstream s;
  s << "<div class=\"figures\">";
  for (const Figure& f : figures) {
    s << "<figure><img alt=\"" << htmlEscape(f.png.filename().string()) << "\"";
    if (displayWidth > 0) s << " width=\"" << displayWidth << "\"";
    s << " src=\"data:image/png;base64," << kPlaceholder << "\"><figcaption>" << htmlEscape(f.caption)
      << "</figcaption></figure>";
    images_.push_back(f.png);
  }
  s << "</div>";
  blocks_.push_back(s.str());
}

void HtmlReport::write(const std::filesystem::path& path) const {
  std::string page =
      "<!DOCTYPE html>\n<html lang=\"en\" data-status=\"loading\">\n<head>\n<meta "
      "charset=\"utf-8\">\n<title>" +
      htmlEscape(title_) + "</title>\n<script>" + kErrorScript + "</script>\n<style>" + kStyle +
      "</style>\n</head>\n<body>\n<h1>" + htmlEscape(title_) + "</h1>\n";
  std::size_t image = 0;
  for (const std::string& block : blocks_) {
    for (const char c : block) {
      if (c != kPlaceholder) {
        page += c;
        continue;
      }
      // PNGs only: a report never embeds more than a few tens of MiB.
      page += base64(readInputFile(images_[image++], std::uint64_t(64) << 20));
    }
    page += "\n";
  }
  page += "<p style=\"color:#777\">Written by iblx; self-contained: every image is embedded.</p>\n<script>" +
          std::string(kScript) + "</script>\n</body>\n</html>\n";
  writeFileAtomically(path, page);
}

}  // namespace iblx::cli
