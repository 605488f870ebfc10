#pragma once
/// @file
/// A checker of the Prometheus text exposition format 0.0.4, written from the format's
/// description (not from our writer), for tests: every line is a HELP, TYPE or other comment,
/// blank, or a sample `name{label="value",...} value [timestamp]`; names and label names are
/// well-formed; label values use only the \\ \" \n escapes; values parse as floats (or NaN,
/// +Inf, -Inf); HELP and TYPE come at most once per family and before its samples; a family's
/// samples are contiguous; no series repeats; histograms have ascending `le` buckets with
/// non-decreasing counts, a `+Inf` bucket equal to `_count`, and a `_sum`.

#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace retreat::testing::prometheus {

struct Sample {
  std::string name;
  std::map<std::string, std::string> labels;
  double value = 0.0;
};

struct Parsed {
  std::vector<std::string> errors;          ///< empty: the text is valid
  std::vector<Sample> samples;              ///< in order
  std::map<std::string, std::string> types;  ///< family -> type
  /// The value of `name{labels}` (labels as written: key="value" pairs in any order), or NaN.
  double value(const std::string& name, const std::map<std::string, std::string>& labels = {}) const {
    for (const auto& s : samples) {
      if (s.name == name && s.labels == labels) return s.value;
    }
    return std::nan("");
  }
  bool has(const std::string& name) const {
    for (const auto& s : samples) {
      if (s.name == name) return true;
    }
    return false;
  }
};

namespace detail {

inline bool name_start(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c == ':'; }
inline bool name_char(char c) { return name_start(c) || (c >= '0' && c <= '9'); }
inline bool label_start(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
inline bool label_char(char c) { return label_start(c) || (c >= '0' && c <= '9'); }

inline bool parse_float(const std::string& text, double& out) {
  if (text == "NaN") return out = std::nan(""), true;
  if (text == "+Inf" || text == "Inf") return out = HUGE_VAL, true;
  if (text == "-Inf") return out = -HUGE_VAL, true;
  if (text.empty()) return false;
  for (char c : text) {
    if (!((c >= '0' && c <= '9') || c == '.' || c == 'e' || c == 'E' || c == '+' || c == '-')) return false;
  }
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

inline bool valid_name(const std::string& n) {
  if (n.empty() || !name_start(n[0])) return false;
  for (char c : n) {
    if (!name_char(c)) return false;
  }
  return true;
}

/// The family a sample name belongs to, given the TYPE lines seen.
inline std::string family_of(const std::string& name, const std::map<std::string, std::string>& types) {
  for (const char* suffix : {"_bucket", "_sum", "_count"}) {
    const std::string s(suffix);
    if (name.size() > s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0) {
      const auto base = name.substr(0, name.size() - s.size());
      const auto it = types.find(base);
      if (it != types.end() && (it->second == "histogram" || (it->second == "summary" && s != "_bucket"))) return base;
    }
  }
  return name;
}

}  // namespace detail

inline Parsed parse(const std::string& text) {
  Parsed p;
  auto error = [&](std::size_t line, const std::string& what) {
    p.errors.push_back("line " + std::to_string(line) + ": " + what);
  };
  if (!text.empty() && text.back() != '\n') p.errors.push_back("the text does not end with a newline");
  std::set<std::string> help_seen, families_done, series_seen;
  std::set<std::string> sampled;  // families with samples so far
  std::string current_family;
  std::istringstream in(text);
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty()) continue;
    if (line[0] == '#') {
      std::istringstream words(line.substr(1));
      std::string keyword, name;
      words >> keyword >> name;
      if (keyword != "HELP" && keyword != "TYPE") continue;  // a plain comment
      if (!detail::valid_name(name)) {
        error(n, "bad metric name in " + keyword + ": '" + name + "'");
        continue;
      }
      if (sampled.count(name) > 0) error(n, keyword + " for '" + name + "' after its samples");
      if (keyword == "HELP") {
        if (!help_seen.insert(name).second) error(n, "second HELP for '" + name + "'");
        // Only \\ and \n escapes in a docstring.
        const auto doc = line.substr(std::min(line.size(), 7 + name.size() + 1));
        for (std::size_t i = 0; i < doc.size(); ++i) {
          if (doc[i] == '\\') {
            if (i + 1 >= doc.size() || (doc[i + 1] != '\\' && doc[i + 1] != 'n')) error(n, "bad escape in HELP");
            ++i;
          }
        }
      } else {
        std::string type, extra;
        words >> type >> extra;
        if (type != "counter" && type != "gauge" && type != "histogram" && type != "summary" && type != "untyped") {
          error(n, "bad type '" + type + "'");
        }
        if (!extra.empty()) error(n, "text after the type");
        if (!p.types.emplace(name, type).second) error(n, "second TYPE for '" + name + "'");
      }
      continue;
    }
    // A sample.
    Sample s;
    std::size_t i = 0;
    while (i < line.size() && detail::name_char(line[i])) ++i;
    s.name = line.substr(0, i);
    if (!detail::valid_name(s.name)) {
      error(n, "bad metric name '" + s.name + "'");
      continue;
    }
    bool ok = true;
    if (i < line.size() && line[i] == '{') {
      ++i;
      while (ok && i < line.size() && line[i] != '}') {
        std::size_t start = i;
        if (!detail::label_start(line[i])) {
          ok = false;
          break;
        }
        while (i < line.size() && detail::label_char(line[i])) ++i;
        const auto key = line.substr(start, i - start);
        if (i + 1 >= line.size() || line[i] != '=' || line[i + 1] != '"') {
          ok = false;
          break;
        }
        i += 2;
        std::string value;
        bool closed = false;
        while (i < line.size()) {
          const char c = line[i++];
          if (c == '"') {
            closed = true;
            break;
          }
          if (c == '\\') {
            if (i >= line.size()) break;
            const char e = line[i++];
            if (e == '\\') {
              value += '\\';
            } else if (e == '"') {
              value += '"';
            } else if (e == 'n') {
              value += '\n';
            } else {
              ok = false;
              break;
            }
          } else {
            value += c;
          }
        }
        if (!closed) ok = false;
        if (!ok) break;
        if (key.rfind("__", 0) == 0) error(n, "reserved label name '" + key + "'");
        if (!s.labels.emplace(key, value).second) error(n, "label '" + key + "' twice");
        if (i < line.size() && line[i] == ',') ++i;
      }
      if (!ok || i >= line.size() || line[i] != '}') {
        error(n, "bad label set");
        continue;
      }
      ++i;
    }
    if (i >= line.size() || line[i] != ' ') {
      error(n, "no space before the value");
      continue;
    }
    while (i < line.size() && line[i] == ' ') ++i;
    std::istringstream rest(line.substr(i));
    std::string value_text, timestamp, extra;
    rest >> value_text >> timestamp >> extra;
    if (!detail::parse_float(value_text, s.value)) {
      error(n, "bad value '" + value_text + "'");
      continue;
    }
    if (!timestamp.empty()) {
      char* end = nullptr;
      std::strtoll(timestamp.c_str(), &end, 10);
      if (end != timestamp.c_str() + timestamp.size()) error(n, "bad timestamp '" + timestamp + "'");
    }
    if (!extra.empty()) error(n, "text after the timestamp");

    const auto family = detail::family_of(s.name, p.types);
    if (family != current_family) {
      if (families_done.count(family) > 0) error(n, "samples of '" + family + "' are not contiguous");
      if (!current_family.empty()) families_done.insert(current_family);
      current_family = family;
    }
    sampled.insert(family);
    std::string key = s.name + "{";
    for (const auto& [k, v] : s.labels) key += k + "=\"" + v + "\",";
    key += "}";
    if (!series_seen.insert(key).second) error(n, "series repeated: " + key);
    p.samples.push_back(std::move(s));
  }

  // Histograms.
  for (const auto& [family, type] : p.types) {
    if (type != "histogram") continue;
    std::map<std::map<std::string, std::string>, std::vector<std::pair<double, double>>> buckets;
    std::map<std::map<std::string, std::string>, double> counts;
    std::set<std::map<std::string, std::string>> sums;
    for (const auto& s : p.samples) {
      if (s.name == family + "_bucket") {
        auto labels = s.labels;
        const auto le = labels.find("le");
        double bound = 0.0;
        if (le == labels.end() || !detail::parse_float(le->second, bound)) {
          p.errors.push_back(family + ": a bucket without a valid le");
          continue;
        }
        labels.erase(le);
        buckets[labels].emplace_back(bound, s.value);
      } else if (s.name == family + "_count") {
        counts[s.labels] = s.value;
      } else if (s.name == family + "_sum") {
        sums.insert(s.labels);
      } else if (s.name == family) {
        p.errors.push_back(family + ": a histogram sample without _bucket/_sum/_count");
      }
    }
    if (buckets.empty()) p.errors.push_back(family + ": histogram without buckets");
    for (const auto& [labels, b] : buckets) {
      for (std::size_t k = 1; k < b.size(); ++k) {
        if (!(b[k].first > b[k - 1].first)) p.errors.push_back(family + ": le not ascending");
        if (b[k].second < b[k - 1].second) p.errors.push_back(family + ": bucket counts decrease");
      }
      if (b.empty() || !std::isinf(b.back().first)) {
        p.errors.push_back(family + ": no +Inf bucket");
      } else if (counts.count(labels) == 0 || counts.at(labels) != b.back().second) {
        p.errors.push_back(family + ": _count differs from the +Inf bucket");
      }
      if (sums.count(labels) == 0) p.errors.push_back(family + ": no _sum");
    }
  }
  return p;
}

/// All errors on one line each, for a test message.
inline std::string describe(const Parsed& p) {
  std::string out;
  for (const auto& e : p.errors) out += e + "\n";
  return out;
}

}  // namespace retreat::testing::prometheus
