#include "retreat/report/figures.hpp"

#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>

#include "page_parts.hpp"

namespace retreat::report {

namespace {

using nlohmann::json;

[[noreturn]] void bad(const std::string& where, const std::string& what) {
  throw std::invalid_argument("figures: " + where + ": " + what);
}

void require_string(const json& j, const std::string& key, const std::string& where, bool optional) {
  if (!j.contains(key)) {
    if (optional) return;
    bad(where + "." + key, "missing (a string)");
  }
  if (!j[key].is_string()) bad(where + "." + key, "must be a string");
}

/// An array of numbers or nulls; returns its length.
std::size_t numbers(const json& j, const std::string& key, const std::string& where) {
  if (!j.contains(key) || !j[key].is_array()) bad(where + "." + key, "missing (an array of numbers)");
  for (std::size_t i = 0; i < j[key].size(); ++i) {
    const auto& v = j[key][i];
    if (!v.is_number() && !v.is_null()) {
      bad(where + "." + key + "[" + std::to_string(i) + "]", "must be a number or null");
    }
  }
  return j[key].size();
}

void validate_series(const json& s, const std::string& where) {
  if (!s.is_object()) bad(where, "must be an object");
  require_string(s, "label", where, false);
  require_string(s, "kind", where, false);
  const auto kind = s["kind"].get<std::string>();
  if (kind != "line" && kind != "points" && kind != "bars" && kind != "band") {
    bad(where + ".kind = '" + kind + "'", "must be line, points, bars or band");
  }
  require_string(s, "color", where, true);
  const auto n = numbers(s, "x", where);
  if (kind == "band") {
    if (numbers(s, "low", where) != n || numbers(s, "high", where) != n) {
      bad(where, "low and high must have as many values as x");
    }
  } else if (numbers(s, "y", where) != n) {
    bad(where, "y must have as many values as x");
  }
}

/// An array of strings; returns its length.
std::size_t strings(const json& j, const std::string& key, const std::string& where) {
  if (!j.contains(key) || !j[key].is_array()) bad(where + "." + key, "missing (an array of strings)");
  for (std::size_t i = 0; i < j[key].size(); ++i) {
    if (!j[key][i].is_string()) bad(where + "." + key + "[" + std::to_string(i) + "]", "must be a string");
  }
  return j[key].size();
}

void validate_heatmap(const json& h, const std::string& where) {
  if (!h.is_object()) bad(where, "must be an object");
  const auto rows = strings(h, "rows", where);
  const auto columns = strings(h, "columns", where);
  if (rows == 0 || columns == 0) bad(where, "needs at least one row and one column");
  for (const char* key : {"low", "high"}) {
    if (!h.contains(key) || !h[key].is_number()) bad(where + "." + key, "missing (a number)");
  }
  if (!(h["low"].get<double>() < h["high"].get<double>())) bad(where + ".low", "must be below high");
  for (const char* key : {"values", "text"}) {
    if (!h.contains(key)) {
      if (std::string(key) == "text") continue;
      bad(where + "." + key, "missing (one array per row)");
    }
    if (!h[key].is_array() || h[key].size() != rows) bad(where + "." + key, "must have one array per row");
    for (std::size_t r = 0; r < rows; ++r) {
      const std::string row_where = where + "." + key + "[" + std::to_string(r) + "]";
      const auto& row = h[key][r];
      if (!row.is_array() || row.size() != columns) bad(row_where, "must have one cell per column");
      for (const auto& cell : row) {
        const bool ok = std::string(key) == "text" ? cell.is_string() : (cell.is_number() || cell.is_null());
        if (!ok) bad(row_where, std::string(key) == "text" ? "cells must be strings" : "cells must be numbers or null");
      }
    }
  }
}

void validate_figure(const json& f, const std::string& where, std::set<std::string>& ids) {
  if (!f.is_object()) bad(where, "must be an object");
  require_string(f, "id", where, false);
  const auto id = f["id"].get<std::string>();
  if (id.empty() || id.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_") !=
                        std::string::npos) {
    bad(where + ".id = '" + id + "'", "must be letters, digits, - and _");
  }
  if (!ids.insert(id).second) bad(where + ".id = '" + id + "'", "used twice");
  for (const char* key : {"title", "x_label", "y_label"}) require_string(f, key, where, false);
  require_string(f, "note", where, true);
  for (const char* key : {"x_log", "y_log"}) {
    if (f.contains(key) && !f[key].is_boolean()) bad(where + "." + key, "must be true or false");
  }
  for (const char* key : {"x_min", "x_max", "y_min", "y_max"}) {
    if (f.contains(key) && !f[key].is_number()) bad(where + "." + key, "must be a number");
  }
  if (f.contains("heatmap")) {
    validate_heatmap(f["heatmap"], where + ".heatmap");
    if (f.contains("series")) bad(where, "has both series and heatmap");
    return;
  }
  if (!f.contains("series") || !f["series"].is_array() || f["series"].empty()) {
    bad(where + ".series", "missing (a non-empty array)");
  }
  for (std::size_t i = 0; i < f["series"].size(); ++i) {
    validate_series(f["series"][i], where + ".series[" + std::to_string(i) + "]");
  }
}

void validate_table(const json& t, const std::string& where) {
  if (!t.is_object()) bad(where, "must be an object");
  require_string(t, "title", where, false);
  if (!t.contains("columns") || !t["columns"].is_array()) bad(where + ".columns", "missing (an array)");
  if (!t.contains("rows") || !t["rows"].is_array()) bad(where + ".rows", "missing (an array)");
  for (std::size_t i = 0; i < t["rows"].size(); ++i) {
    const auto& row = t["rows"][i];
    if (!row.is_array() || row.size() != t["columns"].size()) {
      bad(where + ".rows[" + std::to_string(i) + "]", "must have one cell per column");
    }
  }
}

}  // namespace

void validate_figures_page(const json& page) {
  if (!page.is_object()) bad("page", "must be an object");
  require_string(page, "title", "page", false);
  require_string(page, "subtitle", "page", true);
  require_string(page, "footer", "page", true);
  if (!page.contains("sections") || !page["sections"].is_array()) bad("sections", "missing (an array)");
  std::set<std::string> ids;
  for (std::size_t i = 0; i < page["sections"].size(); ++i) {
    const auto& s = page["sections"][i];
    const std::string where = "sections[" + std::to_string(i) + "]";
    if (!s.is_object()) bad(where, "must be an object");
    require_string(s, "heading", where, false);
    if (s.contains("text")) {
      if (!s["text"].is_array()) bad(where + ".text", "must be an array of strings");
      for (const auto& p : s["text"]) {
        if (!p.is_string()) bad(where + ".text", "must be an array of strings");
      }
    }
    for (const char* key : {"figures", "tables"}) {
      if (s.contains(key) && !s[key].is_array()) bad(where + "." + key, "must be an array");
    }
    for (std::size_t k = 0; s.contains("figures") && k < s["figures"].size(); ++k) {
      validate_figure(s["figures"][k], where + ".figures[" + std::to_string(k) + "]", ids);
    }
    for (std::size_t k = 0; s.contains("tables") && k < s["tables"].size(); ++k) {
      validate_table(s["tables"][k], where + ".tables[" + std::to_string(k) + "]");
    }
  }
}

std::string render_figures_page(const json& page) {
  validate_figures_page(page);
  std::string html;
  html += "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  html += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  html += "<title>" + detail::html_escape(page["title"].get<std::string>()) + "</title>\n";
  html += "<style>\n" + detail::asset_text("vendor/uPlot.min.css") + "\n" + detail::asset_text("report.css") +
          "\n</style>\n";
  html += "</head>\n<body>\n<main id=\"report\"></main>\n";
  html += "<script>\n" + detail::asset_text("vendor/uPlot.iife.min.js") + "\n</script>\n";
  html += "<script>\nwindow.FIGURES = " + detail::script_json(page) + ";\n</script>\n";
  html += "<script>\n" + detail::asset_text("report-figures.js") + "\n</script>\n";
  html += "</body>\n</html>\n";
  return html;
}

void write_figures_page(const json& page, const std::string& path) {
  const auto html = render_figures_page(page);
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path + ": cannot write");
    out << html;
    if (!out.flush()) throw std::runtime_error(path + ": cannot write");
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace retreat::report
