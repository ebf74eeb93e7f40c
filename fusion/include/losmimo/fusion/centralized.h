#pragma once
// Centralized solution of the paper's problem (eq. 4) with perfect knowledge:
//
//   minimise  sum_n |q_n - qbar_n|^2   subject to   ICN(H(q)) >= alpha
//
// qbar the start positions (3 x Nr, metres), H = placement::ChannelModel::matrix(q). ICN is not
// smooth, so the constraint is replaced by a penalty on the paper's objective f (metrics.h):
//
//   J_mu(q) = sum_n |q_n - qbar_n|^2 + mu f(q),   grad_{q_m} J = 2 (q_m - qbar_m) + mu grad_m f
//
// with grad_m f = placement::UavObjective(swarm, m).gradient_at(q_m). Each J_mu is minimised with
// Ceres' L-BFGS (ceres::GradientProblem). Continuation: mu grows geometrically until ICN >= alpha,
// then a log-bisection on mu lowers the travel while ICN stays >= alpha (each candidate is
// re-checked). J has many local minima, so it is run from several starts and the feasible
// solution of least squared travel is kept:
//   - the start positions (mu from mu_initial upwards);
//   - the lattice URA targets (placement::UraPlanner, UraVariant::kLattice), from mu_max down;
//   - the rigid URA (slots assigned by least total squared distance), from mu_max down;
//   - where the paper's GD (placement::GradientDescentPlanner, no localization or actuation
//     error) first reaches alpha: GD follows the descent flow of f from the start, which finds
//     basins that the penalty continuation from the start positions can miss (J_mu has local
//     minima with ICN < alpha even at mu_max);
//   - the two URA placements themselves when they are feasible (the rigid URA is the fallback
//     that bounds the result by the rigid URA's travel whenever the rigid URA meets alpha).
// f is only a surrogate of the constraint (it penalises every off-diagonal Gram entry, the
// constraint only the extreme eigenvalues), so every feasible candidate is then polished with
// a log barrier on the constraint itself, staying strictly feasible:
//
//   B_t(q) = sum_n |q_n - qbar_n|^2 - t log g(q),   g = lambda_min(G) - alpha^2 lambda_max(G)
//
// G = H^H H; ICN^2 = lambda_min / lambda_max, so g > 0 <=> ICN > alpha. For a simple eigenvalue
// with unit eigenvector v, lambda = sum_n |x_n^T v|^2 (x_n the rows of H) and
//   grad_{q_m} lambda = 2 sum_k Re(conj(x_m^T v) v_k x_mk s_k) u_k
// (s_k, u_k from ChannelModel::row_derivative_terms). t decreases geometrically to t_final;
// the result is within ~t_final of a local optimum of eq. 4.
// The result also reports the lattice and rigid URA placements as baselines.

#include <Eigen/Core>
#include <string>

#include "losmimo/placement/channel.h"
#include "losmimo/placement/scenario.h"

namespace losmimo::fusion {

struct CentralizedConfig {
  double target_icn = 0.95;        // alpha, in (0, 1)
  double mu_initial = 1e-4;        // first penalty weight from the start positions [m^2]
  double mu_growth = 4.0;          // continuation factor (> 1)
  double mu_max = 1e2;             // largest penalty weight tried [m^2]
  int reduce_steps = 8;            // log-bisection steps on mu once feasible
  int max_lbfgs_iterations = 400;  // per J_mu minimisation
  bool start_from_lattice_ura = true;
  bool start_from_rigid_ura = true;
  bool start_from_gd = true;
  int gd_max_iterations = 3000;    // GD iterations for that candidate
  bool barrier_polish = true;      // the log-barrier stage above
  double barrier_t_initial = 1.0;  // [m^2]
  double barrier_t_final = 1e-4;   // [m^2]
  double barrier_t_factor = 0.1;   // in (0, 1)
};

// Throws std::invalid_argument naming the first bad field and its value.
void validate(const CentralizedConfig& config);

// Travel from one placement to another (3 x Nr each).
struct TravelStats {
  double total_m = 0.0;  // sum_n |to_n - from_n|
  double mean_m = 0.0;   // per UAV
  double max_m = 0.0;
  double total_squared_m2 = 0.0;  // sum_n |to_n - from_n|^2 (the eq. 4 objective)
  double mean_squared_m2 = 0.0;
};
TravelStats travel_stats(const Eigen::Matrix3Xd& from_m, const Eigen::Matrix3Xd& to_m);

// J_mu(q) as above; writes grad_q J (3 x Nr) when gradient != nullptr.
double penalized_travel_cost(const placement::ChannelModel& model, const Eigen::Matrix3Xd& start_m, double mu,
                             const Eigen::Matrix3Xd& q_m, Eigen::Matrix3Xd* gradient);

// B_t(q) as above; returns +infinity when g(q) <= 0 (gradient then untouched). Writes
// grad_q B (3 x Nr) when gradient != nullptr. alpha in (0, 1), t > 0.
double barrier_travel_cost(const placement::ChannelModel& model, const Eigen::Matrix3Xd& start_m, double alpha,
                           double t, const Eigen::Matrix3Xd& q_m, Eigen::Matrix3Xd* gradient);

enum class CentralizedStatus { kFeasible, kInfeasible };
enum class CentralizedStart { kStartPositions, kLatticeUra, kRigidUra, kGd, kNone };
std::string to_string(CentralizedStatus status);
std::string to_string(CentralizedStart start);

struct CentralizedResult {
  CentralizedStatus status = CentralizedStatus::kInfeasible;
  CentralizedStart best_start = CentralizedStart::kNone;  // the start the kept solution came from
  bool best_is_raw_ura = false;                           // the kept solution is a URA placement itself, not optimised
  Eigen::Matrix3Xd positions_m;                           // the solution (the start positions when infeasible)
  double icn = 0.0;                                       // of positions_m, by SVD of H
  TravelStats travel;
  double mu = 0.0;        // penalty weight of the kept solution (0 for a raw URA)
  bool polished = false;  // the kept solution went through the barrier stage
  int num_solves = 0;     // L-BFGS minimisations run

  // Baselines with the same perfect knowledge (empty when num_uavs != Nt).
  Eigen::Matrix3Xd lattice_ura_m;
  double lattice_ura_icn = 0.0;
  TravelStats lattice_ura_travel;
  Eigen::Matrix3Xd rigid_ura_m;  // slots assigned by least total squared distance
  double rigid_ura_icn = 0.0;
  TravelStats rigid_ura_travel;
};

// Throws std::invalid_argument for an invalid scenario/config or start_m not 3 x num_uavs.
CentralizedResult solve_centralized(const placement::Scenario& scenario, const Eigen::Matrix3Xd& start_m,
                                    const CentralizedConfig& config);

}  // namespace losmimo::fusion
