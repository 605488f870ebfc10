#pragma once
/// @file
/// A self-contained page of figures (uPlot, its CSS and the page script inlined; no network),
/// for programs that compute their own numbers, such as retreat-experiment. The page is
/// described in JSON and drawn by report-figures.js:
///
///     {"title": "...", "subtitle": "...",
///      "sections": [{"heading": "...", "text": ["paragraph", ...],
///                    "figures": [figure, ...], "tables": [table, ...]}, ...],
///      "footer": "..."}
///
/// figure: {"id": "name" (letters, digits, - and _), "title", "note", "x_label", "y_label",
///          "x_log": false, "y_log": false, "x_min", "x_max", "y_min", "y_max": numbers (optional axis limits),
///          "series": [series, ...]}
/// series: {"label", "kind": "line" | "points" | "bars" | "band", "x": [...], "y": [...],
///          "low": [...], "high": [...] (band: instead of y), "dash": false, "color": "#rrggbb"
///          (optional)}; x values need not be shared between series (the page merges them),
///          null in y leaves a gap.
/// A figure may instead be a heat map, drawn as a table of coloured cells: "heatmap" in place of
/// "series": {"rows": ["row label", ...], "columns": ["column label", ...],
///            "values": [[number or null, ...], ...] (one row per row label, one value per column),
///            "text": [["cell text", ...], ...] (optional, same shape; default: the value),
///            "low": number, "high": number (values from low (green) to high (red); beyond, the end
///            colours; null: grey)}; x_label names the columns and y_label the rows.
/// table: {"title", "columns": ["...", ...], "rows": [[cell, ...], ...]}
///
/// Opening the page with `#only=<id>` shows that one figure alone (for screenshots).

#include <string>

#include <nlohmann/json.hpp>

namespace retreat::report {

/// Checks `page` against the description above (shape only: field types, equal lengths of
/// x and y, known kinds, ids unique and well-formed).
/// @throws std::invalid_argument naming the first bad field, e.g.
///         `figures: sections[0].figures[1].series[0].kind = 'pie': must be line, points, bars or band`.
void validate_figures_page(const nlohmann::json& page);

/// The HTML of the page (validate_figures_page() first).
std::string render_figures_page(const nlohmann::json& page);

/// Writes render_figures_page(page) to `path` through a temporary file, so that a reader never
/// sees half a page. @throws std::runtime_error when the file cannot be written.
void write_figures_page(const nlohmann::json& page, const std::string& path);

}  // namespace retreat::report
