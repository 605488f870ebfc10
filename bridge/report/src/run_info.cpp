#include "retreat/report/run_info.hpp"

#include "retreat/model/optimum.hpp"
#include "retreat/physics/domain.hpp"
#include "retreat/physics/params.hpp"

namespace retreat::report {

telemetry::RunInfo run_info(const scenario::Scenario& s) {
  const auto& a = s.arena;
  const auto domain = physics::domain_of(a);
  telemetry::RunInfo r;
  r.scenario = s.name;
  r.mode = retreat::name_of(s.run.mode);
  r.shape = retreat::name_of(a.shape);
  r.half_x = domain.half_extent().x();
  r.half_y = domain.half_extent().y();
  r.area = domain.area();
  r.lambda_star = model::lambda_star(s.model);
  r.encounter_model = retreat::name_of(a.encounter_model);
  r.robot_radius = a.robot_radius;
  r.delta = s.model.delta;
  r.robots = a.robots_inside + a.robots_waiting;
  r.duration = s.run.duration;
  r.status_period = s.run.status_period;
  r.telemetry_period = s.run.telemetry_period;
  return r;
}

}  // namespace retreat::report
