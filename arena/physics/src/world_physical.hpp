#pragma once
/// @file
/// The physical world (private header; use make_world()).

#include <cstdint>
#include <limits>
#include <vector>

#include "retreat/physics/barrier_certificate.hpp"
#include "retreat/physics/collection_task.hpp"
#include "retreat/physics/encounter_tracker.hpp"
#include "retreat/physics/neighbour_grid.hpp"
#include "retreat/physics/random_walk.hpp"
#include "retreat/physics/unicycle.hpp"
#include "world_base.hpp"

namespace retreat::physics::detail {

/// Unicycles doing the random walk under decentralized barrier certificates. Each physics step:
/// act (Euler-integrate the commands computed at the previous sample, add the step to each
/// inside robot's task-state time), transitions (retreating robots whose footprint is outside D
/// depart; entering robots whose projected point reached the walk region start walking),
/// arrivals, then sense (one grid pass per robot collects partners within 2δ and the
/// neighbours within the barrier's interaction range; encounters, pick-up/drop-off, walk
/// update and the QP follow).
class PhysicalWorld final : public WorldBase {
 public:
  explicit PhysicalWorld(const WorldParams& params);

  void step_tick() override;
  bool set_external_pose(RobotId id, double x, double y, double theta) override;
  bool lose_external(RobotId id) override;
  Telemetry telemetry() const override;
  Poses poses() const override;
  std::vector<ContactRecord> take_contact_records() override { return tracker_.take_records(); }

 private:
  struct Body {
    Pose pose;
    WalkState walk;
    RetreatDetour detour;  ///< how it leaves once it retreats (arena.retreat_unblock)
    Vec2 entry_direction = Vec2::UnitX();
    UnicycleCommand command;
    Rng rng;
    TaskState sensed_state = TaskState::f;
    bool entering = false;
    bool external = false;  ///< a real robot: posed from outside, never moved or commanded here
    /// The last exact clearance of q computed, and where: the clearance is 1-Lipschitz in q, so
    /// clearance(q) ≥ boundary_clearance − |q − boundary_q| while q has not gone far.
    Vec2 boundary_q = Vec2::Zero();
    double boundary_clearance = -std::numeric_limits<double>::infinity();
    /// heading(θ) as the last sense() computed it, and the θ's bits it is for: the next step's
    /// motion reuses it while θ has not changed since (poses set in between are recomputed).
    Vec2 heading = Vec2::UnitX();
    std::uint64_t heading_theta_bits = ~std::uint64_t{0};  // a NaN's bits: no θ matches
    /// The last nearest boundary point computed for this robot's position, and that position's
    /// bits (boundary_at): a retreating robot's departure test and its next sensing ask about
    /// the same position, and each answer costs an ellipse's root.
    BoundaryPoint boundary;
    std::uint64_t boundary_x_bits = ~std::uint64_t{0};  // a NaN's bits: no position matches
    std::uint64_t boundary_y_bits = ~std::uint64_t{0};
  };

  bool is_external_in_d(RobotId id) const;
  /// domain_.nearest_boundary_point(@p p) for @p body's position @p p, computed once per position.
  const BoundaryPoint& boundary_at(Body& body, const Vec2& p) const;

  void on_robot_created(RobotId id) override;
  void on_retreat(RobotId id) override;
  void step_physics();
  bool try_enter(RobotId id);
  void sense(bool initial);

  BarrierCertificate barrier_;
  NeighbourGrid grid_;
  CollectionTask task_;
  EncounterTracker tracker_;
  std::vector<Body> bodies_;     // by id
  std::vector<RobotId> active_;  // robots in D (inside or retreating), ascending id
  std::int64_t step_ = 0;
  std::int64_t substeps_ = 1;
  double dt_ = 0.01;
  double body_inset_ = 0.0;       // r + l: clearance of q that keeps the footprint in D
  double walk_margin_ = 0.0;      // walk_inset − body_inset: where the walk reflects
  double boundary_zone_ = 0.0;    // clearance below which the boundary needs exact treatment
  double entry_clearance_ = 0.0;  // no robot centre this close to an entry point
  std::uint64_t qp_relaxed_ = 0;
  // Snapshot of the robots in D at the last sample, in active_ order.
  std::vector<Vec2> position_;
  std::vector<Vec2> heading_;
  std::vector<Vec2> projected_;
  std::vector<Vec2> entrants_;  // robots placed since the last snapshot
  // Scratch.
  std::vector<HalfPlane> constraints_;
  std::vector<RobotId> partners_;
};

}  // namespace retreat::physics::detail
