#include "retreat/bridge/json.hpp"

#include <cmath>

namespace retreat::bridge {

namespace {

using nlohmann::json;

json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json run_json(const telemetry::RunInfo& r) {
  return {{"scenario", r.scenario},
          {"mode", r.mode},
          {"shape", r.shape},
          {"half_extent", {r.half_x, r.half_y}},
          {"area", number(r.area)},
          {"lambda_star", number(r.lambda_star)},
          {"optimal_population", number(r.optimal_population())},
          {"encounter_model", r.encounter_model},
          {"robot_radius", number(r.robot_radius)},
          {"delta", number(r.delta)},
          {"robots", r.robots},
          {"duration", number(r.duration)},
          {"status_period", number(r.status_period)},
          {"telemetry_period", number(r.telemetry_period)}};
}

json telemetry_json(const wire::ArenaTelemetry& t) {
  return {{"arena_id", t.arena_id},     {"tick", t.tick},
          {"time", number(t.time)},     {"inside", t.inside},
          {"waiting", t.waiting},       {"retreating", t.retreating},
          {"departed", t.departed},     {"lost_agents", t.lost_agents},
          {"true_density", number(t.true_density)}, {"deliveries", t.deliveries},
          {"ticks_per_second", number(t.ticks_per_second)}};
}

json poses_json(const wire::Poses& p) {
  json robots = json::array();
  for (const auto& r : p.robots) {
    robots.push_back({{"id", r.robot_id},
                      {"x", number(r.x)},
                      {"y", number(r.y)},
                      {"theta", number(r.theta)},
                      {"phase", std::string(wire::to_string(r.phase))},
                      {"loaded", r.loaded}});
  }
  const auto points = [](const std::vector<wire::Point2>& v) {
    json out = json::array();
    for (const auto& q : v) out.push_back({number(q.x), number(q.y)});
    return out;
  };
  return {{"arena_id", p.arena_id}, {"tick", p.tick}, {"time", number(p.time)},
          {"robots", robots}, {"pickups", points(p.pickups)}, {"dropoffs", points(p.dropoffs)}};
}

json agent_json(const telemetry::AgentView& a) {
  const auto& s = a.status;
  return {{"robot", s.robot_id},
          {"tick", s.tick},
          {"time", number(s.time)},
          {"deciding", s.deciding},
          {"retreating", s.retreating},
          {"onsets_in_window", s.onsets_in_window},
          {"lambda_hat", number(s.lambda_hat)},
          {"epsilon", number(s.epsilon)},
          {"frames_dropped", s.frames_dropped},
          {"counted", a.counted}};
}

json estimates_json(const telemetry::EstimateHistogram& h) {
  return {{"bin_width", number(h.bin_width)}, {"counts", h.counts}, {"overflow", h.overflow},
          {"count", h.count}, {"mean", number(h.mean())}, {"min", number(h.min)},
          {"max", number(h.max)}};
}

}  // namespace

json point_json(const telemetry::HistoryPoint& p) {
  return {{"time", number(p.time)},
          {"tick", p.tick},
          {"inside", p.inside},
          {"waiting", p.waiting},
          {"retreating", p.retreating},
          {"departed", p.departed},
          {"lost_agents", p.lost_agents},
          {"deliveries", p.deliveries},
          {"true_density", number(p.true_density)},
          {"ticks_per_second", number(p.ticks_per_second)},
          {"estimates", p.estimates},
          {"lambda_hat_mean", number(p.lambda_hat_mean)},
          {"lambda_hat_min", number(p.lambda_hat_min)},
          {"lambda_hat_max", number(p.lambda_hat_max)}};
}

json state_json(const telemetry::Snapshot& s) {
  json j;
  j["run"] = run_json(s.run);
  j["telemetry"] = s.telemetry ? telemetry_json(*s.telemetry) : json(nullptr);
  j["poses"] = s.poses ? poses_json(*s.poses) : json(nullptr);
  j["agents"] = json::array();
  for (const auto& a : s.agents) j["agents"].push_back(agent_json(a));
  j["estimates"] = estimates_json(s.estimates);
  j["history"] = {{"points", s.history_size},
                  {"spacing", number(s.history_spacing)},
                  {"compactions", s.history_compactions},
                  {"last", s.last_point ? point_json(*s.last_point) : json(nullptr)}};
  j["samples"] = {{"arena_telemetry", s.samples.telemetry},
                  {"poses", s.samples.poses},
                  {"agent_status", s.samples.statuses},
                  {"stale", s.samples.stale}};
  j["runs"] = s.runs;
  j["version"] = s.version;
  return j;
}

json history_json(const std::deque<telemetry::HistoryPoint>& history, double spacing,
                  std::uint64_t compactions) {
  json j;
  j["spacing"] = number(spacing);
  j["compactions"] = compactions;
  j["points"] = history.size();
  const auto column = [&](const char* key, auto field) {
    json a = json::array();
    for (const auto& p : history) a.push_back(field(p));
    j[key] = std::move(a);
  };
  using P = telemetry::HistoryPoint;
  column("time", [](const P& p) { return number(p.time); });
  column("tick", [](const P& p) { return json(p.tick); });
  column("inside", [](const P& p) { return json(p.inside); });
  column("waiting", [](const P& p) { return json(p.waiting); });
  column("retreating", [](const P& p) { return json(p.retreating); });
  column("departed", [](const P& p) { return json(p.departed); });
  column("lost_agents", [](const P& p) { return json(p.lost_agents); });
  column("deliveries", [](const P& p) { return json(p.deliveries); });
  column("true_density", [](const P& p) { return number(p.true_density); });
  column("ticks_per_second", [](const P& p) { return number(p.ticks_per_second); });
  column("estimates", [](const P& p) { return json(p.estimates); });
  column("lambda_hat_mean", [](const P& p) { return number(p.lambda_hat_mean); });
  column("lambda_hat_min", [](const P& p) { return number(p.lambda_hat_min); });
  column("lambda_hat_max", [](const P& p) { return number(p.lambda_hat_max); });
  return j;
}

}  // namespace retreat::bridge
