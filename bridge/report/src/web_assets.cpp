#include "retreat/report/web_assets.hpp"

namespace retreat::report {

const WebAsset* find_web_asset(std::string_view name) {
  for (const auto& a : web_assets()) {
    if (a.name == name) return &a;
  }
  return nullptr;
}

std::string_view content_type_for(std::string_view name) {
  const auto ends = [&](std::string_view suffix) {
    return name.size() >= suffix.size() && name.substr(name.size() - suffix.size()) == suffix;
  };
  if (ends(".html")) return "text/html; charset=utf-8";
  if (ends(".js")) return "text/javascript; charset=utf-8";
  if (ends(".css")) return "text/css; charset=utf-8";
  if (ends(".svg")) return "image/svg+xml";
  if (ends(".json")) return "application/json";
  if (ends(".csv")) return "text/csv; charset=utf-8";
  if (ends(".yaml")) return "application/yaml";
  return "application/octet-stream";
}

}  // namespace retreat::report
