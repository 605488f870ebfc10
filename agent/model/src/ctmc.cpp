#include "retreat/model/ctmc.hpp"

#include <Eigen/LU>

#include "retreat/model/encounter.hpp"

namespace retreat::model {

Eigen::Matrix4d generator(const ModelParams& p, double lambda) {
  using S = CtmcState;
  const double collide = omega_c(p, lambda);  // cλ
  const double pick = omega_p(p);             // mλ_p
  const double drop = omega_d(p);             // mλ_d
  Eigen::Matrix4d g = Eigen::Matrix4d::Zero();
  g(S::f, S::l) = pick;
  g(S::f, S::fc) = collide;
  g(S::l, S::f) = drop;
  g(S::l, S::lc) = collide;
  g(S::fc, S::f) = p.rho;
  g(S::lc, S::l) = p.rho;
  for (Eigen::Index row = 0; row < 4; ++row) {
    g(row, row) = -g.row(row).sum();
  }
  return g;
}

Eigen::Vector4d stationary_closed_form(const ModelParams& p, double lambda) {
  using S = CtmcState;
  const double interference = omega_c(p, lambda) / p.rho;  // cλ/ρ
  const double loaded_ratio = p.lambda_p / p.lambda_d;     // π_l / π_f
  Eigen::Vector4d pi;
  pi(S::f) = 1.0 / ((1.0 + loaded_ratio) * (1.0 + interference));
  pi(S::l) = loaded_ratio * pi(S::f);
  pi(S::fc) = interference * pi(S::f);
  pi(S::lc) = interference * pi(S::l);
  return pi;
}

Eigen::Vector4d stationary_numeric(const ModelParams& p, double lambda) {
  // Gᵀπ = 0 has rank 3 for an irreducible chain; replacing its last equation by Σπ = 1
  // makes the system regular.
  Eigen::Matrix4d a = generator(p, lambda).transpose();
  a.row(3).setOnes();
  const Eigen::Vector4d b(0.0, 0.0, 0.0, 1.0);
  return a.fullPivLu().solve(b);
}

double throughput(const ModelParams& p, double lambda) {
  const double transport = p.lambda_p * p.lambda_d / (p.lambda_p + p.lambda_d);
  return 2.0 * p.delta * p.v * transport / (1.0 + omega_c(p, lambda) / p.rho);
}

double output(const ModelParams& p, double lambda) { return throughput(p, lambda) * lambda; }

}  // namespace retreat::model
