#include "retreat/replay/diff.hpp"

#include <algorithm>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include "retreat/core/paths.hpp"
#include "retreat/replay/recording.hpp"

namespace retreat::replay {
namespace {

namespace fs = std::filesystem;

constexpr char chain_magic[8] = {'R', 'T', 'C', 'H', 'A', 'I', 'N', '1'};

std::string phase_name(int phase) {
  if (phase < 0 || phase >= wire::phase_count) return std::to_string(phase);
  return std::string(wire::to_string(static_cast<wire::Phase>(phase)));
}

// ---- run directories ---------------------------------------------------------------------------

std::vector<std::uint64_t> read_chain(const std::string& dir) {
  const auto path = dir + "/chain.bin";
  const auto read = retreat::read_file(path);
  if (!read) {
    throw DiffError("'" + dir + "': no chain.bin (not a run directory, or written before runs recorded their hash chain)");
  }
  const std::string& bytes = *read;
  if (bytes.size() < sizeof chain_magic || std::memcmp(bytes.data(), chain_magic, sizeof chain_magic) != 0) {
    throw DiffError("'" + path + "': not a hash chain (it does not begin with RTCHAIN1)");
  }
  std::vector<std::uint64_t> links;
  // A killed arena may leave half a link at the end: it is left out.
  for (std::size_t at = sizeof chain_magic; at + 8 <= bytes.size(); at += 8) {
    std::uint64_t link = 0;
    for (int i = 0; i < 8; ++i) link |= static_cast<std::uint64_t>(static_cast<unsigned char>(bytes[at + i])) << (8 * i);
    links.push_back(link);
  }
  return links;
}

/// Rows of a CSV file of numbers as text, with its header; a half-written last line left out.
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

Csv read_csv(const std::string& path, const std::string& expected_first_column) {
  auto read = retreat::read_file(path);
  if (!read) throw DiffError("'" + path + "': missing");
  std::string text = std::move(*read);
  if (const auto end = text.rfind('\n'); end != std::string::npos) text.resize(end + 1);
  std::istringstream lines(text);
  Csv csv;
  std::string line;
  const auto split = [](const std::string& l) {
    std::vector<std::string> cells;
    std::istringstream c(l);
    for (std::string cell; std::getline(c, cell, ',');) cells.push_back(cell);
    return cells;
  };
  if (!std::getline(lines, line) || (csv.header = split(line)).empty() || csv.header[0] != expected_first_column) {
    throw DiffError("'" + path + "': its header does not begin with " + expected_first_column);
  }
  std::size_t number = 1;
  while (std::getline(lines, line)) {
    ++number;
    auto cells = split(line);
    if (cells.size() != csv.header.size()) {
      throw DiffError("'" + path + "' line " + std::to_string(number) + ": " + std::to_string(cells.size()) +
                      " cells, the header has " + std::to_string(csv.header.size()));
    }
    csv.rows.push_back(std::move(cells));
  }
  return csv;
}

std::int64_t integer(const std::string& cell, const std::string& path) {
  std::int64_t v = 0;
  const auto [end, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
  if (ec != std::errc() || end != cell.data() + cell.size()) {
    throw DiffError("'" + path + "': '" + cell + "' is not a whole number");
  }
  return v;
}

struct RobotState {
  int phase = -1;  ///< -1: not in the run (yet)
  bool retreat = false;
  bool operator==(const RobotState&) const = default;
};

/// Every robot's (phase, decision) at @p tick, from transitions.csv.
std::map<std::uint32_t, RobotState> states_at(const std::string& dir, std::int64_t tick) {
  const auto path = dir + "/transitions.csv";
  const auto csv = read_csv(path, "tick");
  std::map<std::uint32_t, RobotState> out;
  for (const auto& row : csv.rows) {
    if (row.size() < 4) throw DiffError("'" + path + "': a row with fewer than 4 cells");
    if (integer(row[0], path) > tick) break;  // rows are in tick order
    const auto robot = integer(row[1], path);
    if (robot < 0 || robot > 0xFFFFFFFFLL) throw DiffError("'" + path + "': robot " + row[1] + " out of range");
    out[static_cast<std::uint32_t>(robot)] = RobotState{static_cast<int>(integer(row[2], path)), integer(row[3], path) != 0};
  }
  return out;
}

/// The first telemetry row (by position) whose cells differ, with the column.
struct TelemetryDifference {
  std::int64_t tick = -1;
  std::string column, a, b;
};

std::optional<TelemetryDifference> first_telemetry_difference(const std::string& a, const std::string& b) {
  const auto ta = read_csv(a + "/telemetry.csv", "tick");
  const auto tb = read_csv(b + "/telemetry.csv", "tick");
  if (ta.header != tb.header) return TelemetryDifference{0, "(columns)", "", ""};
  const std::size_t n = std::min(ta.rows.size(), tb.rows.size());
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t c = 0; c < ta.header.size(); ++c) {
      if (ta.rows[i][c] != tb.rows[i][c]) {
        return TelemetryDifference{integer(ta.rows[i][0], a + "/telemetry.csv"), ta.header[c], ta.rows[i][c], tb.rows[i][c]};
      }
    }
  }
  if (ta.rows.size() != tb.rows.size()) {
    const auto& longer = ta.rows.size() > tb.rows.size() ? ta : tb;
    return TelemetryDifference{integer(longer.rows[n][0], "telemetry.csv"), "(rows)",
                               std::to_string(ta.rows.size()) + " rows", std::to_string(tb.rows.size()) + " rows"};
  }
  return std::nullopt;
}

std::string telemetry_line(const TelemetryDifference& d) {
  return "the telemetry first differs at tick " + std::to_string(d.tick) + ": " + d.column + " A " + d.a + ", B " + d.b;
}

// ---- recordings ----------------------------------------------------------------------------------

/// One comparable item of a recording at a tick: who, which field, the value as text.
struct Candidate {
  std::int64_t tick = -1;
  std::string robot, field, a, b;
};

/// Keeps the earliest difference (lowest tick; on a tie, the first found).
void keep(std::optional<Candidate>& best, Candidate c) {
  if (!best || c.tick < best->tick) best = std::move(c);
}

std::string text(double v) {
  std::ostringstream o;
  o.precision(17);
  o << v;
  return o.str();
}

/// Compares two sequences keyed by tick, field by field (@p fields gives (name, value text) pairs).
template <class M>
void compare_by_tick(const std::map<std::int64_t, M>& a, const std::map<std::int64_t, M>& b, const std::string& robot,
                     const std::string& what,
                     const std::function<std::vector<std::pair<std::string, std::string>>(const M&)>& fields,
                     std::optional<Candidate>& best) {
  auto ia = a.begin();
  auto ib = b.begin();
  while (ia != a.end() || ib != b.end()) {
    if (ib == b.end() || (ia != a.end() && ia->first < ib->first)) {
      keep(best, {ia->first, robot, what, "present", "absent"});
      return;
    }
    if (ia == a.end() || ib->first < ia->first) {
      keep(best, {ib->first, robot, what, "absent", "present"});
      return;
    }
    const auto fa = fields(ia->second);
    const auto fb = fields(ib->second);
    for (std::size_t i = 0; i < fa.size(); ++i) {
      if (fa[i].second != fb[i].second) {
        keep(best, {ia->first, robot, what + "." + fa[i].first, fa[i].second, fb[i].second});
        return;
      }
    }
    ++ia;
    ++ib;
  }
}

}  // namespace

DiffResult diff_run_directories(const std::string& a, const std::string& b) {
  const auto ca = read_chain(a);
  const auto cb = read_chain(b);
  DiffResult r;
  const std::size_t n = std::min(ca.size(), cb.size());
  std::size_t k = 0;
  while (k < n && ca[k] == cb[k]) ++k;
  const auto telemetry = first_telemetry_difference(a, b);
  std::ostringstream out;
  if (k == n && ca.size() == cb.size()) {
    if (!telemetry) {
      r.identical = true;
      out << "identical: " << ca.size() << " ticks, the same trajectory hash chain and telemetry\n";
    } else {
      r.tick = telemetry->tick;
      r.field = telemetry->column;
      r.a = telemetry->a;
      r.b = telemetry->b;
      out << "differ: " << telemetry_line(*telemetry) << " (every robot's phase and decision agree at every tick)\n";
    }
    r.report = out.str();
    return r;
  }
  r.tick = static_cast<std::int64_t>(k);
  if (k == n) {
    // One run stopped earlier; they agree up to there.
    r.field = "(end)";
    r.a = std::to_string(ca.size()) + " ticks";
    r.b = std::to_string(cb.size()) + " ticks";
    out << "differ at tick " << k << ": " << (ca.size() < cb.size() ? "A" : "B") << " ends there, after " << n
        << " ticks that agree; the other goes on to " << std::max(ca.size(), cb.size()) << " ticks\n";
  } else {
    const auto sa = states_at(a, r.tick);
    const auto sb = states_at(b, r.tick);
    std::map<std::uint32_t, std::pair<RobotState, RobotState>> differing;
    for (const auto& [robot, state] : sa) {
      const auto it = sb.find(robot);
      const RobotState other = it == sb.end() ? RobotState{} : it->second;
      if (!(state == other)) differing[robot] = {state, other};
    }
    for (const auto& [robot, state] : sb) {
      if (sa.count(robot) == 0) differing[robot] = {RobotState{}, state};
    }
    if (differing.empty()) {
      r.field = "(records)";
      out << "differ at tick " << k
          << ": the trajectory records differ but no robot's phase or decision does (a robot is missing from one "
             "run's records)\n";
    } else {
      const auto& [robot, states] = *differing.begin();
      const auto& [x, y] = states;
      r.robot = std::to_string(robot);
      const auto value = [](const RobotState& s, bool phase) {
        if (s.phase < 0) return std::string("absent");
        return phase ? phase_name(s.phase) : std::string(s.retreat ? "retreat" : "stay");
      };
      const bool phase = x.phase != y.phase;
      r.field = phase ? "phase" : "decision";
      r.a = value(x, phase);
      r.b = value(y, phase);
      out << "differ at tick " << k << ": robot " << robot << " " << r.field << " A " << r.a << ", B " << r.b << '\n';
      if (differing.size() > 1) out << "  " << differing.size() << " robots differ at that tick\n";
    }
  }
  if (telemetry && telemetry->tick < r.tick) {
    // The counts diverged first (a delivery, say): that is the first difference; the robots'
    // phases and decisions follow.
    std::ostringstream first;
    first << "differ at tick " << telemetry->tick << ": telemetry " << telemetry->column << " A " << telemetry->a
          << ", B " << telemetry->b << " (every robot's phase and decision agree until tick " << r.tick << ")\n  then "
          << out.str();
    r.tick = telemetry->tick;
    r.robot.clear();
    r.field = telemetry->column;
    r.a = telemetry->a;
    r.b = telemetry->b;
    r.report = first.str();
    return r;
  }
  if (telemetry) out << "  " << telemetry_line(*telemetry) << '\n';
  r.report = out.str();
  return r;
}

DiffResult diff_recordings(const std::string& a, const std::string& b) {
  Recording ra, rb;
  try {
    ra = load_recording(a);
    rb = load_recording(b);
  } catch (const RecordingError& e) {
    throw DiffError(e.what());
  }
  std::optional<Candidate> best;
  const bool same_mode = ra.scenario.run.plans == rb.scenario.run.plans;
  std::ostringstream notes;
  if (!same_mode) {
    notes << "  A and B answer differently (" << (ra.scenario.run.plans ? "A with plans" : "A per tick") << ", "
          << (rb.scenario.run.plans ? "B with plans" : "B per tick")
          << "): their frames and answers are not compared, their statuses, poses and telemetry are\n";
  }
  // Per robot: frames and answers (same mode only), by tick.
  std::set<std::uint32_t> robots;
  if (same_mode) {
    for (const auto& [id, r] : ra.robots) robots.insert(id);
    for (const auto& [id, r] : rb.robots) robots.insert(id);
  }
  for (const auto id : robots) {
    static const RecordedRobot none;
    const auto& x = ra.robots.count(id) ? ra.robots.at(id) : none;
    const auto& y = rb.robots.count(id) ? rb.robots.at(id) : none;
    std::map<std::int64_t, wire::ProximityFrame> fx, fy;
    for (const auto& f : x.frames) fx.try_emplace(f.sample.tick, f.sample);
    for (const auto& f : y.frames) fy.try_emplace(f.sample.tick, f.sample);
    const std::function<std::vector<std::pair<std::string, std::string>>(const wire::ProximityFrame&)> frame_fields =
        [](const wire::ProximityFrame& f) {
          return std::vector<std::pair<std::string, std::string>>{{"time", text(f.time)},
                                                                  {"phase", phase_name(static_cast<int>(f.phase))},
                                                                  {"in_contact", f.in_contact ? "true" : "false"},
                                                                  {"new_onsets", std::to_string(f.new_onsets)}};
        };
    compare_by_tick(fx, fy, std::to_string(id), "frame", frame_fields, best);
    // Answers by the frame they answer: a decision's tick; a plan's frame, found by its time.
    const auto answers_by_frame = [&](const RecordedRobot& robot, const std::map<std::int64_t, wire::ProximityFrame>& frames) {
      std::map<std::int64_t, wire::Decision> out;
      for (const auto& ans : robot.answers) {
        std::int64_t tick = ans.sample.tick;
        if (ra.scenario.run.plans) {
          tick = -1;
          for (const auto& [t, f] : frames) {
            if (f.time == ans.sample.time) {
              tick = t;
              break;
            }
          }
          if (tick < 0) continue;  // an answer to a frame the recorder missed: not comparable
        }
        out.try_emplace(tick, ans.sample);
      }
      return out;
    };
    const std::function<std::vector<std::pair<std::string, std::string>>(const wire::Decision&)> answer_fields =
        [](const wire::Decision& d) {
          return std::vector<std::pair<std::string, std::string>>{{"retreat", d.retreat ? "true" : "false"},
                                                                  {"tick", std::to_string(d.tick)},
                                                                  {"time", text(d.time)}};
        };
    compare_by_tick(answers_by_frame(x, fx), answers_by_frame(y, fy), std::to_string(id),
                    ra.scenario.run.plans ? "plan" : "decision", answer_fields, best);
  }
  // Statuses, by robot and tick (the per-tick run's statuses whatever the mode).
  std::map<std::uint32_t, std::pair<std::map<std::int64_t, wire::AgentStatus>, std::map<std::int64_t, wire::AgentStatus>>>
      statuses;
  for (const auto& s : ra.statuses) statuses[s.sample.robot_id].first.try_emplace(s.sample.tick, s.sample);
  for (const auto& s : rb.statuses) statuses[s.sample.robot_id].second.try_emplace(s.sample.tick, s.sample);
  const std::function<std::vector<std::pair<std::string, std::string>>(const wire::AgentStatus&)> status_fields =
      [](const wire::AgentStatus& s) {
        return std::vector<std::pair<std::string, std::string>>{{"deciding", s.deciding ? "true" : "false"},
                                                                {"retreating", s.retreating ? "true" : "false"},
                                                                {"onsets_in_window", std::to_string(s.onsets_in_window)},
                                                                {"lambda_hat", text(s.lambda_hat)},
                                                                {"epsilon", text(s.epsilon)},
                                                                {"time", text(s.time)}};
      };
  for (const auto& [id, pair] : statuses) compare_by_tick(pair.first, pair.second, std::to_string(id), "status", status_fields, best);
  // The arena's poses (display only, but where a physical divergence shows first), by robot and tick.
  std::map<std::uint32_t, std::pair<std::map<std::int64_t, wire::RobotPose>, std::map<std::int64_t, wire::RobotPose>>> poses;
  for (const auto& p : ra.poses) {
    for (const auto& r : p.sample.robots) poses[r.robot_id].first.try_emplace(p.sample.tick, r);
  }
  for (const auto& p : rb.poses) {
    for (const auto& r : p.sample.robots) poses[r.robot_id].second.try_emplace(p.sample.tick, r);
  }
  const std::function<std::vector<std::pair<std::string, std::string>>(const wire::RobotPose&)> pose_fields =
      [](const wire::RobotPose& p) {
        return std::vector<std::pair<std::string, std::string>>{{"phase", phase_name(static_cast<int>(p.phase))},
                                                                {"x", text(p.x)},
                                                                {"y", text(p.y)},
                                                                {"theta", text(p.theta)},
                                                                {"loaded", p.loaded ? "true" : "false"}};
      };
  for (const auto& [id, pair] : poses) compare_by_tick(pair.first, pair.second, std::to_string(id), "pose", pose_fields, best);
  // The arena's telemetry, by tick (ticks_per_second is the wall clock's: not compared).
  std::map<std::int64_t, wire::ArenaTelemetry> tx, ty;
  for (const auto& t : ra.telemetry) tx.try_emplace(t.sample.tick, t.sample);
  for (const auto& t : rb.telemetry) ty.try_emplace(t.sample.tick, t.sample);
  const std::function<std::vector<std::pair<std::string, std::string>>(const wire::ArenaTelemetry&)> telemetry_fields =
      [](const wire::ArenaTelemetry& t) {
        return std::vector<std::pair<std::string, std::string>>{
            {"time", text(t.time)},           {"inside", std::to_string(t.inside)},
            {"waiting", std::to_string(t.waiting)}, {"retreating", std::to_string(t.retreating)},
            {"departed", std::to_string(t.departed)}, {"lost_agents", std::to_string(t.lost_agents)},
            {"true_density", text(t.true_density)},   {"deliveries", std::to_string(t.deliveries)}};
      };
  compare_by_tick(tx, ty, "", "telemetry", telemetry_fields, best);

  DiffResult r;
  std::ostringstream out;
  if (!best) {
    r.identical = true;
    if (same_mode) out << "identical: " << ra.robots.size() << " robots' frames and answers, ";
    else out << "identical: ";
    out << ra.statuses.size() << " statuses, " << ra.poses.size() << " poses and " << ra.telemetry.size()
        << " telemetry samples\n";
  } else {
    r.tick = best->tick;
    r.robot = best->robot;
    r.field = best->field;
    r.a = best->a;
    r.b = best->b;
    out << "differ at tick " << r.tick << ": " << (r.robot.empty() ? std::string() : "robot " + r.robot + " ") << r.field
        << " A " << r.a << ", B " << r.b << '\n';
  }
  const auto dropped = [](const Recording& rec) { return rec.recorder_dropped > 0 || rec.undecodable + rec.invalid > 0; };
  if (dropped(ra) || dropped(rb)) {
    notes << "  samples are missing from " << (dropped(ra) && dropped(rb) ? "both recordings" : dropped(ra) ? "A" : "B")
          << " (lost by the recorder, or undecodable): a difference may be a missing sample\n";
  }
  r.report = out.str() + notes.str();
  return r;
}

DiffResult diff_runs(const std::string& a, const std::string& b) {
  std::error_code ec;
  const bool da = fs::is_directory(a, ec);
  const bool db = fs::is_directory(b, ec);
  for (const auto& p : {a, b}) {
    if (!fs::exists(p, ec)) throw DiffError("'" + p + "': no such file or directory");
  }
  if (da != db) throw DiffError("'" + a + "' and '" + b + "': one is a run directory, the other a recording; give two of a kind");
  return da ? diff_run_directories(a, b) : diff_recordings(a, b);
}

}  // namespace retreat::replay
