#pragma once
/// @file
/// The kinetic world (private header; use make_world()).

#include <vector>

#include "world_base.hpp"

namespace retreat::physics::detail {

/// No positions: each robot in D is the CTMC of MODEL.md §3 plus the onset process the agents
/// count, simulated exactly in continuous time (next-event) within each tick:
///  - onsets: Poisson, rate Ω_c = 4δ(4/π)v·(N_D − 1)/|D| with N_D the robots in D (inside and
///    retreating) at the start of the tick, in every state: the estimator counts every robot
///    that comes within 2δ, in contact or not;
///  - contact: an onset while free starts a contact; a contact ends at rate ρ. An onset during a
///    contact is counted but does not restart it: by memorylessness the end would have the same
///    law, and this is exactly the CTMC's fc→f / lc→l rate ρ, so the contact fraction is
///    (Ω_c/ρ)/(1 + Ω_c/ρ);
///  - task: pick-up at Ω_p = 2δvλ_p while free and not in contact, drop-off at Ω_d = 2δvλ_d
///    while loaded and not in contact (robots inside only);
///  - retreat: the robot keeps having encounters (MODEL.md §7.5) and departs a fixed drive-out
///    time after the command: the mean distance from a uniform point of D to ∂D divided by v
///    (for a disc of radius R, R/(3v));
///  - arrivals enter at the end of the tick in which they are due (no room is needed).
/// O(N + events) per tick, one 32-byte generator per robot (seed_for(seed, id, kinetic)).
class KineticWorld final : public WorldBase {
 public:
  explicit KineticWorld(const WorldParams& params);

  void step_tick() override;
  Poses poses() const override;
  std::vector<ContactRecord> take_contact_records() override;

  /// The fixed drive-out time of a retreating robot [s].
  double drive_out_time() const noexcept { return drive_out_time_; }

 private:
  struct Agent {
    Rng rng;
    double contact_start = 0.0;
    double leave_at = 0.0;
  };

  void on_robot_created(RobotId id) override;
  void on_retreat(RobotId id) override;
  void simulate(RobotId id, double from, double to, double omega_c);

  std::vector<Agent> agents_;    // by id
  std::vector<RobotId> active_;  // robots in D, ascending id
  double drive_out_time_ = 0.0;
  double c_ = 0.0;  // 4δ(4/π)v [m²/s]
  double omega_p_ = 0.0;
  double omega_d_ = 0.0;
  std::vector<ContactRecord> records_;
};

}  // namespace retreat::physics::detail
