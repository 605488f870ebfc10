// Uses the installed package: the paper's λ* and an in-memory round trip.
#include <cmath>
#include <cstdio>

#include "retreat/model/optimum.hpp"
#include "retreat/transport/factory.hpp"

int main() {
  const double lambda_star = retreat::model::lambda_star(retreat::model::ModelParams{});
  auto t = retreat::transport::make_transport("inmemory", {});
  auto w = t->create_writer<retreat::wire::Decision>({"consumer/robot_1/decision", {}});
  auto r = t->create_reader<retreat::wire::Decision>({"consumer/robot_1/decision", {}});
  w.write({1, 5, 0.15, true});
  const auto got = r.take();
  const bool ok = std::abs(lambda_star - 1.5076) < 1e-4 && got.size() == 1 && got[0].tick == 5;
  std::printf("lambda_star=%.4f received=%zu vendors=%zu\n", lambda_star, got.size(),
              retreat::transport::available_vendors().size());
  return ok ? 0 : 1;
}
