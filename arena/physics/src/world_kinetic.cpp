#include "world_kinetic.hpp"

#include <algorithm>
#include <cmath>

#include "retreat/core/seed.hpp"

namespace retreat::physics::detail {
namespace {

constexpr double pi = 3.14159265358979323846;

/// Mean distance from a uniform point of @p domain to its boundary, by the midpoint rule on a
/// 200 × 200 grid over the bounding box (relative error well below 1 %).
double mean_boundary_distance(const Domain& domain) {
  constexpr int n = 200;
  const Vec2& half = domain.half_extent();
  double sum = 0.0;
  std::size_t count = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const Vec2 p(half.x() * (2.0 * (i + 0.5) / n - 1.0), half.y() * (2.0 * (j + 0.5) / n - 1.0));
      if (domain.contains(p)) {
        sum -= domain.signed_distance(p);
        ++count;
      }
    }
  }
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

}  // namespace

KineticWorld::KineticWorld(const WorldParams& params)
    : WorldBase(params),
      drive_out_time_(mean_boundary_distance(domain_) / params.v),
      c_(4.0 * params.delta * (4.0 / pi) * params.v),
      omega_p_(2.0 * params.delta * params.v * params.lambda_p),
      omega_d_(2.0 * params.delta * params.v * params.lambda_d) {
  init_population();
  for (RobotId id = 0; id < params.robots_inside; ++id) {
    active_.push_back(id);
  }
  build_frames();
}

void KineticWorld::on_robot_created(RobotId id) {
  agents_.push_back({Rng(retreat::seed_for(params_.seed, id, retreat::Stream::kinetic)), 0.0, 0.0});
}

void KineticWorld::on_retreat(RobotId id) { agents_[id].leave_at = time_ + drive_out_time_; }

void KineticWorld::step_tick() {
  const double from = time_;
  const double to = static_cast<double>(tick_ + 1) * params_.tick_dt;
  const auto in_domain = static_cast<double>(active_.size());
  const double omega_c = in_domain >= 2.0 ? c_ * (in_domain - 1.0) / domain_.area() : 0.0;
  bool departed = false;
  for (const RobotId id : active_) {
    simulate(id, from, to, omega_c);
    departed = departed || stats_[id].phase == Phase::departed;
  }
  if (departed) {
    active_.erase(std::remove_if(active_.begin(), active_.end(),
                                 [&](RobotId id) { return stats_[id].phase == Phase::departed; }),
                  active_.end());
  }
  time_ = to;
  ++tick_;
  admit_arrivals(time_, [&](RobotId id) {
    active_.push_back(id);  // ids enter in ascending order, so active_ stays sorted
    return true;
  });
  build_frames();
}

void KineticWorld::simulate(RobotId id, double from, double to, double omega_c) {
  Agent& agent = agents_[id];
  RobotStats& stats = stats_[id];
  const bool retreating = stats.phase == Phase::retreating;
  const double until = retreating ? std::min(to, agent.leave_at) : to;
  double now = from;
  for (;;) {
    const bool contact = in_contact_[id] != 0;
    const bool working = stats.phase == Phase::inside && !contact;
    const double rate_end = contact ? params_.rho : 0.0;
    const double rate_task = working ? (stats.loaded ? omega_d_ : omega_p_) : 0.0;
    const double total = omega_c + rate_end + rate_task;
    const double wait = agent.rng.exponential(total);
    const double next = now + wait;
    const double span = std::min(next, until) - now;
    if (stats.phase == Phase::inside) {
      stats.state_time[static_cast<std::size_t>(task_state(stats.loaded, contact))] += span;
    }
    if (next >= until) {
      now = until;
      break;
    }
    now = next;
    const double pick = agent.rng.uniform() * total;
    if (pick < omega_c) {
      add_onsets(id, 1);
      if (!contact) {
        in_contact_[id] = 1;
        agent.contact_start = now;
      }
    } else if (pick < omega_c + rate_end) {
      in_contact_[id] = 0;
      if (params_.record_encounters) {
        records_.push_back({id, no_robot, agent.contact_start, now});
      }
    } else if (stats.loaded) {
      stats.loaded = false;
      ++stats.deliveries;
      ++deliveries_;
    } else {
      stats.loaded = true;
      ++stats.pickups;
    }
  }
  if (retreating && now >= agent.leave_at) {
    if (in_contact_[id] != 0 && params_.record_encounters) {
      records_.push_back({id, no_robot, agent.contact_start, now});
    }
    depart(id, agent.leave_at);
  }
}

Poses KineticWorld::poses() const {
  Poses out;
  out.tick = tick_;
  out.time = time_;
  return out;
}

std::vector<ContactRecord> KineticWorld::take_contact_records() {
  std::vector<ContactRecord> out;
  out.swap(records_);
  return out;
}

}  // namespace retreat::physics::detail
