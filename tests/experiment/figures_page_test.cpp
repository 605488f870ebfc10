// The bridge's figures page (retreat/report/figures.hpp), which retreat-experiment draws with:
// a page description is checked field by field, and the page carries it whole, with uPlot and
// the page script inlined.

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "retreat/report/figures.hpp"
#include "retreat/testing/process.hpp"

namespace {

using nlohmann::json;

json page_with(const json& series) {
  return {{"title", "t"},
          {"sections", {{{"heading", "h"},
                         {"text", {"a <b> & c"}},
                         {"figures", json::array({{{"id", "f-1"}, {"title", "T"}, {"x_label", "x"},
                                                   {"y_label", "y"}, {"series", series}}})},
                         {"tables", {{{"title", "tab"}, {"columns", {"a", "b"}}, {"rows", {{1, "two"}}}}}}}}}};
}

json line(const json& x, const json& y) { return {{"label", "l"}, {"kind", "line"}, {"x", x}, {"y", y}}; }

std::string error_of(const json& page) {
  try {
    retreat::report::validate_figures_page(page);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(FiguresPage, AcceptsEveryKindOfSeries) {
  const json series = json::array({line({0, 1, 2}, {1.5, nullptr, 3}),
                       {{"label", "p"}, {"kind", "points"}, {"x", {0.5}}, {"y", {2}}},
                       {{"label", "b"}, {"kind", "bars"}, {"x", {0, 1}}, {"y", {4, 5}}, {"color", "#123456"}},
                       {{"label", "band"}, {"kind", "band"}, {"x", {0, 1}}, {"low", {1, 2}}, {"high", {3, 4}}}});
  EXPECT_EQ(error_of(page_with(series)), "");
}

TEST(FiguresPage, NamesTheFirstBadField) {
  EXPECT_EQ(error_of(page_with(json::array({{{"label", "l"}, {"kind", "pie"}, {"x", {1}}, {"y", {1}}}}))),
            "figures: sections[0].figures[0].series[0].kind = 'pie': must be line, points, bars or band");
  EXPECT_EQ(error_of(page_with(json::array({line({1, 2}, {1})}))),
            "figures: sections[0].figures[0].series[0]: y must have as many values as x");
  EXPECT_EQ(error_of(page_with(json::array({line({1, "two"}, {1, 2})}))),
            "figures: sections[0].figures[0].series[0].x[1]: must be a number or null");
  EXPECT_EQ(error_of(page_with(json::array())), "figures: sections[0].figures[0].series: missing (a non-empty array)");
  auto twice = page_with(json::array({line({1}, {1})}));
  twice["sections"].push_back(twice["sections"][0]);
  EXPECT_EQ(error_of(twice), "figures: sections[1].figures[0].id = 'f-1': used twice");
  auto bad_row = page_with(json::array({line({1}, {1})}));
  bad_row["sections"][0]["tables"][0]["rows"][0] = {1};
  EXPECT_EQ(error_of(bad_row), "figures: sections[0].tables[0].rows[0]: must have one cell per column");
}

json heatmap_page(const json& heatmap) {
  return {{"title", "t"},
          {"sections", {{{"heading", "h"},
                         {"figures", json::array({{{"id", "m"}, {"title", "M"}, {"x_label", "x"}, {"y_label", "y"},
                                                   {"heatmap", heatmap}}})}}}}};
}

TEST(FiguresPage, AcceptsAHeatMapAndNamesItsFirstBadField) {
  const json good = {{"rows", {"a", "b"}}, {"columns", {"x"}}, {"values", {{0.1}, {nullptr}}},
                     {"text", {{"one"}, {"two"}}}, {"low", 0}, {"high", 1}};
  EXPECT_EQ(error_of(heatmap_page(good)), "");
  auto no_text = good;
  no_text.erase("text");
  EXPECT_EQ(error_of(heatmap_page(no_text)), "");
  auto short_row = good;
  short_row["values"][1] = json::array();
  EXPECT_EQ(error_of(heatmap_page(short_row)), "figures: sections[0].figures[0].heatmap.values[1]: must have one cell per column");
  auto reversed = good;
  reversed["low"] = 2;
  EXPECT_EQ(error_of(heatmap_page(reversed)), "figures: sections[0].figures[0].heatmap.low: must be below high");
  auto text_number = good;
  text_number["text"][0][0] = 3;
  EXPECT_EQ(error_of(heatmap_page(text_number)), "figures: sections[0].figures[0].heatmap.text[0]: cells must be strings");
  auto both = heatmap_page(good);
  both["sections"][0]["figures"][0]["series"] = json::array({line({1}, {1})});
  EXPECT_EQ(error_of(both), "figures: sections[0].figures[0]: has both series and heatmap");
}

TEST(FiguresPage, CarriesItsDataWithEverythingInlined) {
  const auto page = page_with(json::array({line({0, 1}, {2, 3})}));
  const auto html = retreat::report::render_figures_page(page);
  const std::string start = "window.FIGURES = ";
  const auto from = html.find(start);
  ASSERT_NE(from, std::string::npos);
  const auto to = html.find(";\n</script>", from);
  ASSERT_NE(to, std::string::npos);
  EXPECT_EQ(json::parse(html.substr(from + start.size(), to - from - start.size())), page);
  // "<" never appears raw inside the script (the text "a <b> & c" is escaped as \u003c).
  EXPECT_EQ(html.substr(from, to - from).find('<'), std::string::npos);
  EXPECT_NE(html.find("uPlot"), std::string::npos);
  EXPECT_NE(html.find("FIGURES"), std::string::npos);
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
}

TEST(FiguresPage, IsWrittenWholeOrNotAtAll) {
  const auto dir = std::filesystem::temp_directory_path() / "retreat-figures-page-test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto path = (dir / "report.html").string();
  retreat::report::write_figures_page(page_with(json::array({line({0}, {1})})), path);
  EXPECT_EQ(retreat::testing::read_file(path), retreat::report::render_figures_page(page_with(json::array({line({0}, {1})}))));
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  EXPECT_THROW(retreat::report::write_figures_page(page_with(json::array({line({0}, {1})})), (dir / "no" / "x.html").string()),
               std::runtime_error);
}

}  // namespace
