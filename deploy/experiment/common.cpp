#include "retreat/experiment/common.hpp"

#include "retreat/agent/controller_registry.hpp"
#include "retreat/core/paths.hpp"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <exception>
#include <fstream>
#include <mutex>
#include <thread>

namespace retreat::experiment {
namespace {

/// NaN and infinities (which nlohmann writes as null anyway) made explicit, recursively.
nlohmann::json sanitised(const nlohmann::json& j) {
  if (j.is_number_float()) return finite_or_null(j.get<double>());
  if (j.is_array() || j.is_object()) {
    nlohmann::json out = j;
    for (auto& v : out) v = sanitised(v);
    return out;
  }
  return j;
}

}  // namespace

std::string scenario_file(const Common& common, const std::string& name) {
  const std::string path = common.scenarios_dir + "/" + name;
  if (!retreat::is_regular_file(path)) {
    throw UsageError("--scenarios '" + common.scenarios_dir + "': no " + name +
                     " there (the directory of the shipped scenarios, deploy/scenarios)");
  }
  return path;
}

void make_run_dir(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(dir, ec) && !(fs::is_directory(dir, ec) && fs::is_empty(dir, ec))) {
    throw UsageError("--out '" + dir + "': exists and is not an empty directory (give a new one)");
  }
  fs::create_directories(dir, ec);
  if (ec) throw UsageError("--out '" + dir + "': cannot create it (" + ec.message() + ")");
}

void write_text(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    out << text;
    if (!out.flush()) throw RunFailure("cannot write '" + tmp + "'");
  }
  std::filesystem::rename(tmp, path);
}

void write_json(const std::string& path, const nlohmann::json& j) { write_text(path, sanitised(j).dump(2) + '\n'); }

unsigned worker_count(std::optional<unsigned> jobs) {
  return jobs.value_or(scenario::core_count());
}

void for_each_index(std::size_t n, unsigned jobs, const std::function<void(std::size_t)>& fn) {
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  const auto work = [&] {
    for (std::size_t i = next++; i < n; i = next++) {
      try {
        fn(i);
      } catch (...) {
        const std::lock_guard lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        next = n;  // the others finish what they began and take nothing more
      }
    }
  };
  const auto threads = static_cast<std::size_t>(std::max(1u, jobs));
  std::vector<std::thread> helpers;
  for (std::size_t t = 1; t < std::min(threads, n); ++t) helpers.emplace_back(work);
  work();
  for (auto& h : helpers) h.join();
  if (failure) std::rethrow_exception(failure);
}

std::vector<std::string> compared_controllers(const Common& common) {
  std::vector<std::string> rules;
  for (const auto& name : agent::controller_names()) {
    const bool asked = common.controllers.empty() ||
                       std::find(common.controllers.begin(), common.controllers.end(), name) != common.controllers.end();
    if (name == "paper" || asked) rules.push_back(name);
  }
  return rules;
}

void check_controllers(const std::vector<std::string>& names) {
  std::string text;  // as given, for the message
  for (const auto& name : names) text += (text.empty() ? "" : ",") + name;
  std::string registered;
  for (const auto& name : agent::controller_names()) registered += (registered.empty() ? "" : ", ") + name;
  for (auto it = names.begin(); it != names.end(); ++it) {
    if (!agent::is_controller_name(*it)) {
      throw UsageError("--controllers '" + text + "': '" + *it + "' is not a registered controller (" + registered +
                       ")");
    }
    if (std::find(names.begin(), it, *it) != it) {
      throw UsageError("--controllers '" + text + "': '" + *it + "' is named twice");
    }
  }
}

std::string with_overrides(const std::vector<std::string>& overrides) {
  std::string text;
  for (const auto& o : overrides) text += (text.empty() ? ", scenarios with --set " : ", ") + o;
  return text;
}

std::vector<QueueCase> queue_cases(const Common& common) {
  return {{"finite", "finite queue (robotarium-2019)", scenario_file(common, "robotarium-2019.yaml")},
          {"endless", "endless queue (steady-influx)", scenario_file(common, "steady-influx.yaml")}};
}

CsvWriter::CsvWriter(const std::string& path, const std::vector<std::string>& header)
    : path_(path), columns_(header.size()), file_(std::fopen(path.c_str(), "w")) {
  if (file_ == nullptr) throw RunFailure("cannot write '" + path + "'");
  for (std::size_t i = 0; i < header.size(); ++i) std::fprintf(file_, "%s%s", i ? "," : "", header[i].c_str());
  std::fputc('\n', file_);
}

CsvWriter::~CsvWriter() {
  if (file_ != nullptr) std::fclose(file_);
}

void CsvWriter::row(const std::vector<nlohmann::json>& cells) {
  if (cells.size() != columns_) throw std::logic_error(path_ + ": a row with the wrong number of cells");
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (i > 0) std::fputc(',', file_);
    const auto& c = cells[i];
    if (c.is_string()) {
      std::fputs(c.get<std::string>().c_str(), file_);
    } else if (c.is_number_integer() || c.is_number_unsigned()) {
      std::fputs(c.dump().c_str(), file_);
    } else if (c.is_number() && std::isfinite(c.get<double>())) {
      std::fprintf(file_, "%.9g", c.get<double>());
    }
  }
  std::fputc('\n', file_);
}

void CsvWriter::close() {
  if (file_ == nullptr) return;
  const bool ok = std::fflush(file_) == 0 && std::ferror(file_) == 0;
  std::fclose(file_);
  file_ = nullptr;
  if (!ok) throw RunFailure("cannot write '" + path_ + "'");
}

std::string fixed(double value, int digits) {
  if (!std::isfinite(value)) return "–";
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, value);
  return text;
}

nlohmann::json finite_or_null(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr); }

double round6(double v) {
  if (!std::isfinite(v) || v == 0.0) return v;
  const double scale = std::pow(10.0, 5 - std::floor(std::log10(std::fabs(v))));
  return std::round(v * scale) / scale;
}

}  // namespace retreat::experiment
