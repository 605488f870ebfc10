#pragma once
/// @file
/// The dashboard's files, compiled into the program (bridge/web, and uPlot from the npm
/// registry, installed at build time): no files to find at run time, no network.

#include <string_view>
#include <vector>

namespace retreat::report {

struct WebAsset {
  std::string_view name;  ///< e.g. `index.html`, `vendor/uPlot.iife.min.js`
  std::string_view data;
};

/// Every embedded file (generated at build time).
const std::vector<WebAsset>& web_assets();

/// The asset called `name`, or nullptr.
const WebAsset* find_web_asset(std::string_view name);

/// Content-Type for a file name by its extension (`application/octet-stream` when unknown).
std::string_view content_type_for(std::string_view name);

}  // namespace retreat::report
