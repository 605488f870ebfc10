#include "retreat/arena/run_recorder.hpp"

#include <openssl/evp.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "retreat/core/paths.hpp"
#include "retreat/model/optimum.hpp"
#include "retreat/physics/domain.hpp"
#include "retreat/physics/params.hpp"

namespace retreat::arena {
namespace {

constexpr std::size_t pending_limit = 64 * 1024;
constexpr char chain_magic[8] = {'R', 'T', 'C', 'H', 'A', 'I', 'N', '1'};

}  // namespace

struct TrajectoryHash::State {
  EVP_MD_CTX* ctx = EVP_MD_CTX_new();
};

TrajectoryHash::TrajectoryHash() : state_(std::make_unique<State>()), pending_(pending_limit) {
  if (state_->ctx == nullptr || EVP_DigestInit_ex(state_->ctx, EVP_sha256(), nullptr) != 1) {
    throw std::runtime_error("OpenSSL: cannot initialise SHA-256");
  }
}

TrajectoryHash::~TrajectoryHash() { EVP_MD_CTX_free(state_->ctx); }

void TrajectoryHash::flush() {
  EVP_DigestUpdate(state_->ctx, pending_.data(), used_);
  used_ = 0;
}

std::uint64_t TrajectoryHash::link() {
  flush();
  auto& state = *state_;
  EVP_MD_CTX* copy = EVP_MD_CTX_new();
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int size = 0;
  if (copy == nullptr || EVP_MD_CTX_copy_ex(copy, state.ctx) != 1 || EVP_DigestFinal_ex(copy, digest, &size) != 1) {
    EVP_MD_CTX_free(copy);
    throw std::runtime_error("OpenSSL: cannot copy a SHA-256 state");
  }
  EVP_MD_CTX_free(copy);
  std::uint64_t link = 0;
  for (int i = 0; i < 8; ++i) link |= static_cast<std::uint64_t>(digest[i]) << (8 * i);
  return link;
}

std::string TrajectoryHash::finish() {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int size = 0;
  flush();
  EVP_DigestFinal_ex(state_->ctx, digest, &size);
  std::ostringstream out;
  for (unsigned int i = 0; i < size; ++i) {
    out << std::hex << std::setw(2) << std::setfill('0') << static_cast<int>(digest[i]);
  }
  return out.str();
}

namespace {

/// The complete lines of `path` (a half-written last line left out), and truncates the file to
/// them. Missing file: no lines.
std::vector<std::string> complete_lines(const std::string& path) {
  const auto read = retreat::read_file(path);
  if (!read) return {};
  const std::string& text = *read;
  const auto end = text.rfind('\n');
  const std::size_t keep = end == std::string::npos ? 0 : end + 1;
  std::filesystem::resize_file(path, keep);
  std::vector<std::string> lines;
  std::istringstream rows(text.substr(0, keep));
  for (std::string line; std::getline(rows, line);) lines.push_back(line);
  return lines;
}

}  // namespace

std::string RunRecorder::recorded_run_in(const std::string& dir) {
  for (const char* name : {"telemetry.csv", "summary.json"}) {
    const auto path = (std::filesystem::path(dir) / name).string();
    if (retreat::exists(path)) return path;
  }
  return {};
}

RunRecorder::RunRecorder(const std::string& dir, const scenario::Scenario& scenario,
                         const std::string& scenario_yaml, bool resume)
    : dir_(dir), scenario_(scenario) {
  if (const auto recorded = recorded_run_in(dir_); !resume && !recorded.empty()) {
    throw std::invalid_argument("--out '" + dir_ + "': holds a recorded run (" + recorded +
                                "); give a new directory (--resume continues a run an arena left)");
  }
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) throw std::runtime_error("--out '" + dir_ + "': cannot create the directory: " + ec.message());
  const auto mode = resume ? std::ios::out | std::ios::app : std::ios::out | std::ios::trunc;
  if (resume) {
    const auto rows = complete_lines(dir_ + "/telemetry.csv");
    if (rows.size() > 1) resumable_tick_ = std::stoll(rows.back().substr(0, rows.back().find(',')));
    for (const auto& row : complete_lines(dir_ + "/retreats.csv")) {
      if (row.empty() || !std::isdigit(static_cast<unsigned char>(row[0]))) continue;  // header
      const auto comma = row.find(',');
      journal_.emplace(std::stoll(row.substr(0, comma)),
                       static_cast<std::uint32_t>(std::stoul(row.substr(comma + 1))));
    }
    if (scenario.arena.record_encounters) complete_lines(dir_ + "/encounters.csv");
  } else {
    std::ofstream(dir_ + "/scenario.yaml") << scenario_yaml;
  }
  const bool fresh = !resume || resumable_tick_ == 0;
  telemetry_.open(dir_ + "/telemetry.csv", fresh ? std::ios::out | std::ios::trunc : mode);
  if (!telemetry_) throw std::runtime_error("--out '" + dir_ + "': cannot write telemetry.csv");
  if (fresh) {
    telemetry_ << "tick,time,inside,waiting,retreating,departed,true_density,deliveries,onsets,"
                  "free,loaded,free_colliding,loaded_colliding\n";
  }
  retreats_.open(dir_ + "/retreats.csv", fresh ? std::ios::out | std::ios::trunc : mode);
  if (fresh) retreats_ << "tick,robot\n" << std::flush;
  // The hash chain and the transitions are rewritten whole: a resumed arena replays every tick
  // before it takes over, and records them again.
  chain_.open(dir_ + "/chain.bin", std::ios::out | std::ios::trunc | std::ios::binary);
  chain_.write(chain_magic, sizeof chain_magic);
  transitions_.open(dir_ + "/transitions.csv", std::ios::out | std::ios::trunc);
  transitions_ << "tick,robot,phase,retreat\n";
  if (!chain_ || !transitions_) throw std::runtime_error("--out '" + dir_ + "': cannot write chain.bin and transitions.csv");
  if (scenario.arena.record_encounters) {
    encounters_.open(dir_ + "/encounters.csv", fresh ? std::ios::out | std::ios::trunc : mode);
    if (fresh) encounters_ << "robot,other,onset_time,end_time\n";
  }
}

void RunRecorder::record_retreat(std::int64_t tick, std::uint32_t robot) {
  retreats_ << tick << ',' << robot << '\n' << std::flush;
}

void RunRecorder::record_state(std::int64_t tick, std::uint32_t robot, std::uint8_t phase, bool retreat) {
  if (robot >= last_state_.size()) last_state_.resize(robot + 1, 0xFFFF);
  const auto state = static_cast<std::uint16_t>(phase | (retreat ? 1U << 8 : 0U));
  if (last_state_[robot] == state) return;
  constexpr auto retreating = static_cast<std::uint8_t>(physics::Phase::retreating);
  constexpr auto departed = static_cast<std::uint8_t>(physics::Phase::departed);
  const bool was_retreating = (last_state_[robot] & 0xFFU) == retreating;
  last_state_[robot] = state;
  if (robot >= retreat_started_.size()) retreat_started_.resize(robot + 1, -1);
  if (phase == retreating && !was_retreating) {
    retreat_started_[robot] = tick;
  } else if (phase == departed && retreat_started_[robot] >= 0) {
    ++retreats_completed_;
    longest_completed_retreat_ =
        std::max(longest_completed_retreat_, tick - retreat_started_[robot]);
    retreat_started_[robot] = -1;
  }
  char row[64];
  char* at = std::to_chars(row, row + 40, tick).ptr;
  *at++ = ',';
  at = std::to_chars(at, row + 52, robot).ptr;
  *at++ = ',';
  *at++ = static_cast<char>('0' + phase % 10);
  *at++ = ',';
  *at++ = retreat ? '1' : '0';
  *at++ = '\n';
  transitions_.write(row, at - row);
}

void RunRecorder::record_link(std::int64_t tick, std::uint64_t link) {
  if (tick != next_link_tick_) {
    throw std::logic_error("chain.bin: the link of tick " + std::to_string(tick) + " after tick " +
                           std::to_string(next_link_tick_ - 1));
  }
  ++next_link_tick_;
  char bytes[8];
  for (int i = 0; i < 8; ++i) bytes[i] = static_cast<char>(link >> (8 * i));
  chain_.write(bytes, sizeof bytes);
}

void RunRecorder::record_tick(const physics::Telemetry& t, bool write) {
  population_.emplace_back(t.time, t.inside);
  last_ = t;
  if (!write) return;
  // std::to_chars, not operator<<: the same text (a double in general form with 6 significant
  // digits is printf's %.6g, what a default stream writes) at a fraction of the cost per tick.
  // 13 cells of at most 20 characters each and their separators always fit.
  char row[512];
  char* at = row;
  char* const end = row + sizeof row - 1;  // room for the newline
  const auto cell = [&](auto value, bool first = false) {
    if (!first && at != end) *at++ = ',';
    if constexpr (std::is_floating_point_v<decltype(value)>) {
      at = std::to_chars(at, end, value, std::chars_format::general, 6).ptr;
    } else {
      at = std::to_chars(at, end, value).ptr;
    }
  };
  cell(t.tick, true);
  cell(t.time);
  cell(t.inside);
  cell(t.waiting);
  cell(t.retreating);
  cell(t.departed);
  cell(t.true_density);
  cell(t.deliveries);
  cell(t.onsets);
  for (const auto n : t.state_counts) cell(n);
  *at++ = '\n';
  telemetry_.write(row, static_cast<std::streamsize>(at - row));
  if (flush_each_tick_) {
    chain_.flush();
    transitions_.flush();
    telemetry_.flush();  // a killed arena leaves every tick it stepped (--resume)
  }
}

void RunRecorder::record_contacts(const std::vector<physics::ContactRecord>& records) {
  if (!encounters_.is_open()) return;
  for (const auto& r : records) {
    encounters_ << r.robot << ',' << r.other << ',' << r.start << ',' << r.end << '\n';
  }
}

void RunRecorder::finish(const physics::World& world, const std::vector<AgentRecord>& agents,
                         const RunSummary& summary) {
  telemetry_.flush();
  chain_.flush();
  transitions_.flush();
  if (encounters_.is_open()) encounters_.flush();
  {
    std::ofstream out(dir_ + "/agents.csv");
    out << "robot,agent_matched,agent_lost,lost_at,retreated,retreat_at,entered_at,departed_at,"
           "onsets,pickups,deliveries\n";
    for (const auto& a : agents) {
      if (a.robot >= world.robot_count()) continue;
      const auto& s = world.robot_stats(a.robot);
      out << a.robot << ',' << a.matched << ',' << a.lost << ',' << a.lost_at << ','
          << a.retreated << ',' << a.retreat_at << ',' << s.entered_at << ',' << s.departed_at
          << ',' << s.onsets << ',' << s.pickups << ',' << s.deliveries << '\n';
    }
  }
  const auto& p = world.params();
  const auto domain = physics::domain_of(p);
  const double lambda_star = model::lambda_star(scenario_.model);
  // The last 300 s of run.duration. A swarm that emptied (nobody inside, driving out or
  // waiting) ends the run early and stays empty: its missing ticks count as zero robots, so the
  // mean is not taken over the crowded time before the end. A run cut short with robots in it
  // (stopped, or its agents lost) has no such continuation: its mean is over its own last 300 s.
  const double end_time = population_.empty() ? 0.0 : population_.back().first;
  const bool emptied = !population_.empty() && last_.inside == 0 && last_.retreating == 0 &&
                       last_.waiting == 0 && end_time < scenario_.run.duration - 1e-9;
  const double span_end = emptied ? scenario_.run.duration : end_time;
  double sum = 0.0;
  std::size_t count = 0;
  for (const auto& [time, inside] : population_) {
    if (time >= span_end - 300.0 - 1e-9) {
      sum += inside;
      ++count;
    }
  }
  if (emptied) {
    // Ticks are evenly spaced at the world's dt; the ticks after the end add zeros.
    const double dt = world.params().tick_dt;
    count += static_cast<std::size_t>(std::llround((span_end - std::max(end_time, span_end - 300.0)) / dt));
  }
  nlohmann::json j;
  j["scenario"] = scenario_.name;
  j["seed"] = scenario_.seed;
  j["dds"] = summary.dds;
  j["mode"] = std::string(retreat::name_of(scenario_.run.mode));
  j["controller"] = scenario_.agent.controller;
  j["encounter_model"] = std::string(retreat::name_of(p.encounter_model));
  j["area"] = domain.area();
  j["lambda_star"] = lambda_star;
  j["optimal_population"] = lambda_star * domain.area();
  j["population"]["final"] = last_.inside;
  j["population"]["mean_last_300s"] = count > 0 ? sum / static_cast<double>(count) : 0.0;
  j["population"]["emptied_at"] = emptied ? nlohmann::json(end_time) : nlohmann::json(nullptr);
  j["run_duration"] = scenario_.run.duration;
  j["ticks"] = summary.ticks;
  j["simulated_seconds"] = last_.time;
  j["wall_seconds"] = summary.wall_seconds;
  j["ticks_per_second"] = summary.wall_seconds > 0 ? static_cast<double>(summary.ticks) / summary.wall_seconds : 0.0;
  j["agents"]["started"] = summary.agents_started;
  j["agents"]["lost"] = summary.agents_lost;
  j["agents"]["retreated"] = std::count_if(agents.begin(), agents.end(), [](const auto& a) { return a.retreated; });
  j["robots"]["departed"] = last_.departed;
  j["robots"]["waiting"] = last_.waiting;
  j["deliveries"] = last_.deliveries;
  j["decisions_dropped"] = summary.decisions_dropped;
  j["frames_resent"] = summary.frames_resent;
  j["slow_answers"] = summary.slow_answers;
  j["decisions_received"] = summary.decisions_received;
  j["decisions_planned"] = summary.decisions_planned;
  if (summary.resumed_at_tick >= 0) j["resumed_at_tick"] = summary.resumed_at_tick;
  if (scenario_.arena.external_robots > 0) {
    const auto& e = summary.external;
    j["external"] = {{"robots", scenario_.arena.external_robots},
                     {"poses_accepted", e.poses_accepted},
                     {"poses_invalid", e.poses_invalid},
                     {"poses_clock_back", e.poses_clock_back},
                     {"poses_jumped", e.poses_jumped},
                     {"frozen", e.frozen},
                     {"lost", e.lost}};
  }
  // How long robots took to drive out, from the first tick their frame said retreating to the
  // first that said departed (a robot that left in the last step, after the last frame, at the
  // last tick). Retreats still under way at the end count up to the last tick: a crowd of
  // retreating robots can hold each other still under the barrier certificates for the rest of
  // the run (docs/experiments.md, "Retreats that never end").
  std::uint64_t completed = retreats_completed_;
  std::int64_t longest_completed = longest_completed_retreat_;
  std::uint64_t under_way = 0;
  std::int64_t longest_under_way = 0;
  for (std::size_t id = 0; id < retreat_started_.size(); ++id) {
    if (retreat_started_[id] < 0) continue;
    const std::int64_t ticks = last_.tick - retreat_started_[id];
    const auto robot = static_cast<physics::RobotId>(id);
    if (id < world.robot_count() && world.robot_stats(robot).phase == physics::Phase::departed) {
      ++completed;
      longest_completed = std::max(longest_completed, ticks);
    } else {
      ++under_way;
      longest_under_way = std::max(longest_under_way, ticks);
    }
  }
  const double tick_dt = world.params().tick_dt;
  j["retreats"] = {{"completed", completed},
                   {"longest_completed_seconds", static_cast<double>(longest_completed) * tick_dt},
                   {"under_way", under_way},
                   {"longest_under_way_seconds", static_cast<double>(longest_under_way) * tick_dt}};
  j["commands"]["accepted"] = last_.commands.accepted;
  j["commands"]["rejected_not_inside"] = last_.commands.rejected_not_inside;
  j["commands"]["rejected_unknown"] = last_.commands.rejected_unknown;
  j["trajectory_sha256"] = summary.trajectory_sha256;
  const std::string tmp = dir_ + "/summary.json.tmp";
  std::ofstream(tmp) << j.dump(2) << '\n';
  std::filesystem::rename(tmp, dir_ + "/summary.json");  // readers never see half a summary
}

}  // namespace retreat::arena
