#include "world_physical.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include "retreat/core/seed.hpp"
#include "retreat/physics/placement.hpp"

namespace retreat::physics::detail {
namespace {

BarrierParams barrier_params(const WorldParams& p) {
  BarrierParams b;
  b.gamma = p.gamma;
  b.safety_distance = p.safety_distance;
  b.projection_distance = p.projection_distance;
  b.boundary_gain = p.boundary_gain;
  b.max_speed = p.max_speed;
  b.max_turn_rate = p.max_turn_rate;
  b.dt = p.physics_dt;
  return b;
}

/// "Room to enter": no robot centre within 2·D_s + 2l of the entry point, so that the newcomer
/// starts with both barrier functions comfortably positive.
double entry_clearance(const WorldParams& p) {
  return 2.0 * p.safety_distance + 2.0 * p.projection_distance;
}

NeighbourGrid make_grid(const WorldParams& p, const Domain& domain, double range) {
  // Robots are at most r + one step outside D (entering, or about to depart).
  const Vec2 margin = Vec2::Constant(2.0 * p.robot_radius + p.max_speed * p.physics_dt);
  const double cell =
      std::max({range, 2.0 * p.delta, entry_clearance(p) + p.max_speed * p.physics_dt});
  return NeighbourGrid(-domain.half_extent() - margin, domain.half_extent() + margin, cell);
}

}  // namespace

PhysicalWorld::PhysicalWorld(const WorldParams& params)
    : WorldBase(params),
      barrier_(barrier_params(params)),
      grid_(make_grid(params, domain_, barrier_.interaction_range())),
      task_(domain_, params.lambda_p, params.lambda_d, params.delta, world_rng_),
      tracker_(params.record_encounters),
      substeps_(substeps_per_tick(params)),
      dt_(params.physics_dt),
      body_inset_(params.robot_radius + params.projection_distance),
      walk_margin_(walk_inset(params) - body_inset_),
      entry_clearance_(entry_clearance(params)) {
  // Below this clearance of q the walk may reflect or the boundary constraint may bind
  // (α·c < u_max); above it both are inactive and the exact ellipse distance is not needed.
  const double u_max =
      std::hypot(params.max_speed, params.projection_distance * params.max_turn_rate);
  boundary_zone_ = std::max(walk_margin_, u_max / params.boundary_gain) + 1e-9;
  init_population();
  const std::vector<Pose> start =
      place_robots(domain_, params.robots_inside, walk_inset(params), params.projection_distance,
                   params.safety_distance, world_rng_);
  for (RobotId id = 0; id < params.robots_inside; ++id) {
    Body& body = bodies_[id];
    body.pose = start[id];
    body.walk = start_walk(heading(body.pose.theta), 0.0, params.tumble_rate, body.rng);
    active_.push_back(id);
  }
  sense(true);
  build_frames();
}

void PhysicalWorld::on_robot_created(RobotId id) {
  bodies_.emplace_back();
  bodies_[id].rng = Rng(retreat::seed_for(params_.seed, id, retreat::Stream::robot_motion));
  bodies_[id].external = id < params_.external_robots;
}

bool PhysicalWorld::is_external_in_d(RobotId id) const {
  return id < bodies_.size() && bodies_[id].external &&
         (stats_[id].phase == Phase::inside || stats_[id].phase == Phase::retreating);
}

bool PhysicalWorld::set_external_pose(RobotId id, double x, double y, double theta) {
  if (!is_external_in_d(id) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(theta)) return false;
  bodies_[id].pose.position = Vec2(x, y);
  bodies_[id].pose.theta = theta;
  return true;
}

bool PhysicalWorld::lose_external(RobotId id) {
  if (!is_external_in_d(id)) return false;
  tracker_.update(id, {}, time_);  // ends its contacts (the partners see it gone too)
  depart(id, time_);
  active_.erase(std::remove(active_.begin(), active_.end(), id), active_.end());
  return true;
}

void PhysicalWorld::on_retreat(RobotId id) {
  bodies_[id].entering = false;
  bodies_[id].detour = {};
}

void PhysicalWorld::step_tick() {
  for (std::int64_t k = 0; k < substeps_; ++k) {
    step_physics();
  }
  ++tick_;
  build_frames();
}

void PhysicalWorld::step_physics() {
  // Act.
  for (const RobotId id : active_) {
    Body& body = bodies_[id];
    if (stats_[id].phase == Phase::inside) {
      stats_[id].state_time[static_cast<std::size_t>(body.sensed_state)] += dt_;
    }
    if (!body.external) {
      const bool sensed = std::bit_cast<std::uint64_t>(body.pose.theta) == body.heading_theta_bits;
      body.pose = integrate_euler(body.pose, sensed ? body.heading : heading(body.pose.theta), body.command, dt_);
    }
  }
  ++step_;
  time_ = static_cast<double>(step_) * dt_;

  // Transitions.
  bool departed = false;
  for (const RobotId id : active_) {
    Body& body = bodies_[id];
    if (stats_[id].phase == Phase::retreating || body.external) {
      // A real robot leaves by its own motion, told to or not.
      if (boundary_at(body, body.pose.position).signed_distance >= params_.robot_radius) {
        tracker_.update(id, {}, time_);  // ends its contacts (the partners see it gone too)
        depart(id, time_);
        departed = true;
      }
    } else if (body.entering) {
      const Vec2 q = projected_point(body.pose, params_.projection_distance);
      if (-domain_.signed_distance(q) - body_inset_ >= walk_margin_) {
        body.entering = false;
        body.walk = start_walk(body.entry_direction, time_, params_.tumble_rate, body.rng);
      }
    }
  }
  if (departed) {
    active_.erase(std::remove_if(active_.begin(), active_.end(),
                                 [&](RobotId id) { return stats_[id].phase == Phase::departed; }),
                  active_.end());
  }

  // Arrivals.
  entrants_.clear();
  admit_arrivals(time_, [&](RobotId id) { return try_enter(id); });

  sense(false);
}

bool PhysicalWorld::try_enter(RobotId id) {
  // Up to 8 boundary points per step; if none has room, the robot stays due and tries again.
  const double slack = params_.max_speed * dt_;  // snapshot positions are one step old
  const double clear2 = (entry_clearance_ + slack) * (entry_clearance_ + slack);
  for (int attempt = 0; attempt < 8; ++attempt) {
    const BoundaryPoint entry = domain_.sample_boundary(world_rng_);
    // Footprint just outside, touching ∂D, facing inwards.
    const Vec2 p = entry.point + params_.robot_radius * entry.outward_normal;
    bool room = true;
    grid_.for_each_candidate(
        p, [&](std::uint32_t k) { room = room && (position_[k] - p).squaredNorm() >= clear2; });
    for (const Vec2& other : entrants_) {
      room = room && (other - p).squaredNorm() >= clear2;
    }
    if (!room) {
      continue;
    }
    Body& body = bodies_[id];
    body.pose.position = p;
    body.pose.theta = std::atan2(-entry.outward_normal.y(), -entry.outward_normal.x());
    body.entry_direction = -entry.outward_normal;
    body.entering = true;
    body.command = {};
    // Ids enter in ascending order (the queue is in id order), so active_ stays sorted.
    active_.push_back(id);
    entrants_.push_back(p);
    return true;
  }
  return false;
}

const BoundaryPoint& PhysicalWorld::boundary_at(Body& body, const Vec2& p) const {
  const auto x = std::bit_cast<std::uint64_t>(p.x());
  const auto y = std::bit_cast<std::uint64_t>(p.y());
  if (x != body.boundary_x_bits || y != body.boundary_y_bits) {
    body.boundary = domain_.nearest_boundary_point(p);
    body.boundary_x_bits = x;
    body.boundary_y_bits = y;
  }
  return body.boundary;
}

void PhysicalWorld::sense(bool initial) {
  const std::size_t n = active_.size();
  const double l = params_.projection_distance;
  position_.resize(n);
  heading_.resize(n);
  projected_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    Body& body = bodies_[active_[k]];
    const Pose& pose = body.pose;
    position_[k] = pose.position;
    heading_[k] = heading(pose.theta);
    projected_[k] = pose.position + l * heading_[k];
    body.heading = heading_[k];
    body.heading_theta_bits = std::bit_cast<std::uint64_t>(pose.theta);
  }
  grid_.build(position_);

  const double contact2 = 4.0 * params_.delta * params_.delta;
  const double range2 = barrier_.interaction_range() * barrier_.interaction_range();
  for (std::size_t k = 0; k < n; ++k) {
    const RobotId id = active_[k];
    Body& body = bodies_[id];
    RobotStats& stats = stats_[id];
    const SensedBody self{position_[k], heading_[k], projected_[k]};

    // Neighbours: partners within 2δ, and barrier constraints within the interaction range.
    constraints_.clear();
    barrier_.add_limits(constraints_, self.e);
    partners_.clear();
    grid_.for_each_candidate(self.p, [&](std::uint32_t m) {
      if (m == k) {
        return;
      }
      const double d2 = (position_[m] - self.p).squaredNorm();
      if (d2 <= contact2) {
        partners_.push_back(active_[m]);
      }
      if (d2 <= range2) {
        barrier_.add_neighbour(constraints_, self, {position_[m], heading_[m], projected_[m]});
      }
    });
    std::sort(partners_.begin(), partners_.end());

    // Encounters.
    if (initial) {
      tracker_.initialize(id, partners_);
    } else {
      add_onsets(id, tracker_.update(id, partners_, time_));
    }
    in_contact_[id] = partners_.empty() ? 0 : 1;

    if (body.external) {
      body.sensed_state = task_state(stats.loaded, in_contact_[id] != 0);
      continue;  // a real robot does its own task and moves by itself
    }

    // Collection task (robots inside only; a retreating robot carries its load out).
    if (stats.phase == Phase::inside) {
      if (!stats.loaded) {
        if (task_.try_pick_up(self.p, world_rng_)) {
          stats.loaded = true;
          ++stats.pickups;
        }
      } else if (task_.can_drop_off(self.p)) {
        stats.loaded = false;
        ++stats.deliveries;
        ++deliveries_;
      }
    }
    body.sensed_state = task_state(stats.loaded, in_contact_[id] != 0);

    // Desired velocity of the projected point.
    Vec2 u_hat;
    const bool retreating = stats.phase == Phase::retreating;
    Vec2 outward = Vec2::Zero();  // a retreating robot's: at its nearest boundary point
    if (retreating) {
      outward = boundary_at(body, self.p).outward_normal;
      u_hat = params_.v * retreat_direction(body.detour, outward);
    } else if (body.entering) {
      u_hat = params_.v * body.entry_direction;
    } else {
      apply_tumbles(body.walk, time_, params_.tumble_rate, body.rng);
      // Two lower bounds of the clearance, and the exact one (an ellipse's costs a root search)
      // only if both are below the zone: past it, the exact clearance changes nothing.
      if (domain_.clearance_lower_bound(self.q) - body_inset_ < boundary_zone_ &&
          body.boundary_clearance - (self.q - body.boundary_q).norm() < boundary_zone_) {
        const BoundaryPoint boundary = domain_.nearest_boundary_point(self.q);
        const double clearance = -boundary.signed_distance - body_inset_;
        body.boundary_q = self.q;
        body.boundary_clearance = clearance;
        if (clearance <= walk_margin_) {
          reflect_if_outward(body.walk, boundary.outward_normal);
        }
        barrier_.add_boundary(constraints_, boundary.outward_normal, clearance);
      }
      u_hat = params_.v * body.walk.direction;
    }

    const QpResult result = solve_barrier_qp(u_hat, constraints_);
    if (result.status == QpStatus::relaxed || result.status == QpStatus::stopped) {
      ++qp_relaxed_;
    }
    body.command = barrier_.to_command(self, result.u);
    if (stats.phase == Phase::inside && !body.entering) {
      unblock_if_stalled(body.walk, result.u, params_.v, time_, params_.unblock_time, body.rng);
    } else if (retreating && params_.retreat_unblock) {
      detour_if_stalled(body.detour, result.u, outward, params_.v, time_, params_.unblock_time, body.rng);
    }
  }
}

Telemetry PhysicalWorld::telemetry() const {
  Telemetry t = WorldBase::telemetry();
  t.qp_relaxed = qp_relaxed_;
  return t;
}

Poses PhysicalWorld::poses() const {
  Poses out;
  out.tick = tick_;
  out.time = time_;
  out.robots.reserve(active_.size());
  for (const RobotId id : active_) {
    const Pose& pose = bodies_[id].pose;
    out.robots.push_back({id, pose.position.x(), pose.position.y(), pose.theta, stats_[id].phase,
                          bodies_[id].entering, stats_[id].loaded, in_contact_[id] != 0});
  }
  out.pickups = task_.pickups();
  out.dropoffs = task_.dropoffs();
  return out;
}

}  // namespace retreat::physics::detail
