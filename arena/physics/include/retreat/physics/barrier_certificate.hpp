#pragma once
/// @file
/// Decentralized barrier certificates for unicycles (MODEL.md §6): each robot i builds its own
/// half-planes in the velocity u of its projected point q_i = p_i + l·e_i from what it senses
/// (neighbours' centres and headings within interaction_range()), solves the QP exactly
/// (barrier_qp.hpp) and maps u to (v, ω) = (eᵀu, nᵀu/l).
///
/// Per neighbour j, two constraints, each robot taking half of the pairwise condition:
///  - steering (Robotarium form, on projected points):
///      −2(q_i − q_j)ᵀ u ≤ B(h_q),   h_q = ‖q_i − q_j‖² − D_s²;
///  - safety (on centres, through v = e_iᵀu only):
///      −2((p_i − p_j)ᵀe_i) e_iᵀ u ≤ B(h_c),   h_c = ‖p_i − p_j‖² − D_s²;
///  with B(h) = min((γ/2)·max(h,0)³, max(h,0)/(4·dt)).
/// The steering constraint makes robots slide around each other. The safety constraint makes the
/// guarantee exact in discrete time: under forward Euler p moves by exactly v·e·dt, so the sum of
/// both robots' halves gives h_c(t+dt) ≥ h_c − 2·dt·B(h_c) + ‖Δp_i − Δp_j‖² ≥ h_c/2 > 0: no two
/// centres ever come closer than D_s, whatever γ. (The steering constraint alone would only
/// guarantee it in continuous time: Euler moves q by u·dt + O(l(ω·dt)²).) The cap h/(4dt) only
/// matters far from contact, where (γ/2)h³ exceeds any reachable speed anyway.
///
/// Boundary (walking robots only; entering and retreating robots cross ∂D on purpose):
///      n_outᵀ u ≤ α·c,   c = −sd(q) − (r + l)  (the clearance of q),
/// which keeps q at least r + l inside D, hence the whole footprint inside D (‖p − q‖ = l).
/// Limits: |e_iᵀu| ≤ max_speed and |n_iᵀu| ≤ l·max_turn_rate, four more half-planes, so the
/// optimum needs no clamping afterwards (clamping would break the certificate).
/// Every constraint with b ≥ 0 contains u = 0, so the only way the polygon can be empty is a
/// negative boundary clearance (discretisation drift of q, ≤ 0.1 mm): then the QP is relaxed.

#include <vector>

#include "retreat/physics/barrier_qp.hpp"
#include "retreat/physics/types.hpp"
#include "retreat/physics/unicycle.hpp"

namespace retreat::physics {

/// The numbers the barrier certificate needs (copied from WorldParams).
struct BarrierParams {
  double gamma = 100.0;               ///< γ [1/(m⁴·s)]
  double safety_distance = 0.13;      ///< D_s [m]
  double projection_distance = 0.04;  ///< l [m]
  double boundary_gain = 30.0;        ///< α [1/s]
  double max_speed = 0.2;             ///< [m/s]
  double max_turn_rate = 3.6;         ///< [rad/s]
  double dt = 0.01;                   ///< physics step [s]
};

/// What robot i senses about itself or a neighbour: centre, unit heading and projected point.
struct SensedBody {
  Vec2 p;  ///< centre [m]
  Vec2 e;  ///< unit heading
  Vec2 q;  ///< projected point p + l·e [m]
};

/// Builds the half-planes of one robot's QP. Stateless apart from its parameters.
class BarrierCertificate {
 public:
  explicit BarrierCertificate(const BarrierParams& params);

  const BarrierParams& params() const noexcept { return params_; }

  /// Centre distance beyond which no pairwise constraint can bind for any admissible u
  /// (B(h) ≥ ‖a‖·u_max); constraints of farther pairs are exactly redundant [m].
  double interaction_range() const noexcept { return range_; }

  /// B(h) = min((γ/2)·max(h,0)³, max(h,0)/(4·dt)) [m²/s].
  double barrier_bound(double h) const noexcept;

  /// Appends the four speed and turn-rate limits of a robot with unit heading @p e.
  void add_limits(std::vector<HalfPlane>& out, const Vec2& e) const;

  /// Appends robot @p self's steering and safety constraints with respect to @p other (each
  /// only if it can bind).
  void add_neighbour(std::vector<HalfPlane>& out, const SensedBody& self,
                     const SensedBody& other) const;

  /// Appends the boundary constraint n_outᵀu ≤ α·clearance if it can bind. @p clearance is
  /// −sd(q) − (r + l) [m].
  void add_boundary(std::vector<HalfPlane>& out, const Vec2& outward_normal,
                    double clearance) const;

  /// The unicycle command for the QP's solution @p u (exact inverse of the projection map).
  UnicycleCommand to_command(const SensedBody& self, const Vec2& u) const;

 private:
  BarrierParams params_;
  double u_max_ = 0.0;  // largest |u| the limits admit
  double range_ = 0.0;
};

}  // namespace retreat::physics
