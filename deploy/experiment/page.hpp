#pragma once
/// @file
/// Builders for the figures page (retreat/report/figures.hpp describes its JSON).

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "retreat/experiment/common.hpp"

namespace retreat::experiment {

/// Values rounded to 6 significant digits, null where not finite.
inline nlohmann::json values(const std::vector<double>& v) {
  nlohmann::json out = nlohmann::json::array();
  for (const double x : v) out.push_back(finite_or_null(round6(x)));
  return out;
}

/// A figure without series; add them with series().
inline nlohmann::json figure(const std::string& id, const std::string& title, const std::string& note,
                             const std::string& x_label, const std::string& y_label) {
  return {{"id", id}, {"title", title}, {"note", note}, {"x_label", x_label}, {"y_label", y_label},
          {"series", nlohmann::json::array()}};
}

/// A line, points or bars series.
inline nlohmann::json series(const std::string& label, const std::string& kind, const std::vector<double>& x,
                             const std::vector<double>& y, bool dash = false) {
  return {{"label", label}, {"kind", kind}, {"x", values(x)}, {"y", values(y)}, {"dash", dash}};
}

/// A band between `low` and `high`.
inline nlohmann::json band(const std::string& label, const std::vector<double>& x, const std::vector<double>& low,
                           const std::vector<double>& high) {
  return {{"label", label}, {"kind", "band"}, {"x", values(x)}, {"low", values(low)}, {"high", values(high)}};
}

/// A constant horizontal line over [x0, x1].
inline nlohmann::json level(const std::string& label, double x0, double x1, double y) {
  return series(label, "line", {x0, x1}, {y, y}, true);
}

}  // namespace retreat::experiment
