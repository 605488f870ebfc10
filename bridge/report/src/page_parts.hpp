#pragma once
// Pieces shared by the self-contained pages (report.cpp, figures.cpp): embedded assets, JSON
// safe inside <script>, HTML escaping. Private to retreat::report.

#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "retreat/report/web_assets.hpp"

namespace retreat::report::detail {

/// The embedded file `name` as text; a missing one is a build error, hence logic_error.
inline std::string asset_text(const char* name) {
  const auto* a = find_web_asset(name);
  if (a == nullptr) throw std::logic_error(std::string("report: no embedded asset ") + name);
  return std::string(a->data);
}

/// JSON safe inside <script>: no '<' at all (it only occurs inside strings).
inline std::string script_json(const nlohmann::json& j) {
  const auto text = j.dump();
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    if (c == '<') {
      out += "\\u003c";
    } else {
      out += c;
    }
  }
  return out;
}

inline std::string html_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace retreat::report::detail
