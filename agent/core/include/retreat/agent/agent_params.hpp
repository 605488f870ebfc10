#pragma once
/// @file
/// The agent's parameters (the `agent:` section of a scenario file).

#include <string>

namespace retreat::agent {

/// Parameters of Algorithm 1. Defaults are the Robotarium experiment's (MODEL.md §6).
struct AgentParams {
  double L = 90.0;          ///< L: onset-counting window, also the wait before deciding [s]
  double dt = 0.03;         ///< dt: decision period [s]
  double K_p = 0.03;        ///< K_p: proportional gain of the density controller [1/s]
  double lambda_in = 0.02;  ///< λ_in: influx of robots [robots/(m²·s)]
  std::string controller = "paper";  ///< registered controller name (controller_names())
  /// The robot's sensor as the robot knows it, for the rules that correct their estimate for it
  /// (confident-proportional, adaptive-proportional, influx-matching; `paper` reads its count as
  /// written):
  double missed_onsets = 0.0;  ///< chance that the sensor misses an onset [-], in [0, 1)
  double false_onsets = 0.0;   ///< rate of spurious onsets it reports [1/s], >= 0

  /// Checks: L finite and > 0; dt finite, > 0 and <= L; K_p and lambda_in finite and >= 0;
  /// controller a registered name; missed_onsets in [0, 1); false_onsets finite and >= 0.
  /// @throws std::invalid_argument with a one-line message naming the first bad field as in
  ///         the scenario file, its value and the valid range, e.g.
  ///         `agent.dt = 100: must be > 0 and <= agent.L (90) (s)` or
  ///         `agent.controller = 'foo': must be one of paper`.
  void validate() const;

  /// Visits the `agent.*` keys in scenario-file order, `a(name, member)` (Drake's Serialize()).
  template <class Archive>
  void serialize(Archive& a) {
    a("L", L);
    a("dt", dt);
    a("K_p", K_p);
    a("lambda_in", lambda_in);
    a("controller", controller);
    a("missed_onsets", missed_onsets);
    a("false_onsets", false_onsets);
  }
};

}  // namespace retreat::agent
