#pragma once
// One placement run: a planner iterates over the swarm (one pass over all UAVs per
// iteration, as the paper's master does) until the ICN reaches the target or the cap.
//
// ICN here is over the smaller Gram matrix the swarm keeps (swarm_channel.h): the BS antennas'
// when Nr >= Nt, the UAVs' when Nr < Nt. With channel conditions (channel_conditions.h) the
// stop test reads the master's measured CSI, while the milestones (0.5, 0.95) use the LoS
// channel at the true positions: the geometry of the placement, the same matrix as the stop
// test's without conditions.

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "losmimo/placement/swarm.h"

namespace losmimo::placement {

enum class RunStatus {
  kConverged,        // the ICN reached RunOptions::target_icn
  kIterationCap,     // max_iterations without reaching it
  kUavUnresponsive,  // the planner (the master) lost a UAV: no measurement, no motion
  kNumericalFault,   // a non-finite position, move, channel row, Gram entry or belief
};
// "converged", "iteration_cap", "uav_unresponsive", "numerical_fault".
std::string to_string(RunStatus status);

// Why a planner ends a run early (Planner::fault). status is kUavUnresponsive or
// kNumericalFault; reason names the UAV, the quantity and since when, e.g.
// "UAV 3: no measurement and no motion for 3 iterations (since iteration 5)".
struct PlannerFault {
  RunStatus status = RunStatus::kNumericalFault;
  int uav = -1;  // -1: not one UAV's
  std::string reason;
};

// One distributed placement algorithm (GD, BF, URA, ...).
class Planner {
 public:
  virtual ~Planner() = default;
  virtual std::string name() const = 0;
  // Called once before the first iteration (e.g. the URA assignment).
  virtual void start(Swarm& /*swarm*/) {}
  // One pass over all UAVs; iteration counts from 1.
  virtual void iterate(Swarm& swarm, int iteration) = 0;
  // Set once the planner has found a fault that ends the run (checked after every iterate()).
  virtual std::optional<PlannerFault> fault() const { return std::nullopt; }
  // Where the planner (the master) believes the UAVs are after the last iterate() (3 x Nr), for
  // RunOptions::StopOn::kBelief; nullopt when it keeps no belief (BF: channel only), or before
  // the first iteration.
  virtual std::optional<Eigen::Matrix3Xd> believed_positions() const { return std::nullopt; }
};

// What the master's stop test evaluates (the paper: "c = evalChannelOrthogonality()"):
// kCsi the ICN of the measured channel (the true positions), kBelief the ICN of the channel the
// planner's believed positions would have (Planner::believed_positions(); kCsi when it has none).
enum class StopOn { kCsi, kBelief };
std::string to_string(StopOn stop_on);
StopOn stop_on_from_string(const std::string& name);  // std::invalid_argument for other names

// Which length a distance counts: kTruePath the true straight-line segments flown, kCommanded
// the commanded moves |r| (they differ only under actuation error).
enum class DistanceKind { kTruePath, kCommanded };
std::string to_string(DistanceKind kind);
DistanceKind distance_kind_from_string(const std::string& name);  // std::invalid_argument

struct RunOptions {
  double target_icn = 0.95;
  int max_iterations = 1000;
  bool trace_sinr = false;      // per-iteration SINR of stream 1 of the true channel (an LLT each)
  double noise_variance = 0.1;  // normalised units (Scenario::noise_variance), for trace_sinr
  // false: an iteration whose ICN is proven (icn_below) below every threshold still pending
  // (0.5 and 0.95 until reached, target_icn) skips the eigen-solve and records icn = NaN in
  // the trace. Milestones, status and iterations are the same either way; the experiment's
  // untraced runs use it (runs under errors spend most iterations far below the target).
  bool full_icn_trace = true;
  StopOn stop_on = StopOn::kCsi;
  // The distances of the trace, the milestones and RunResult's per-UAV distances.
  DistanceKind distance = DistanceKind::kTruePath;
  // The milestones' distance counts the BF probe flights too (placement + probe).
  bool milestone_distance_includes_probes = false;
  // Keep the true positions after every iteration in RunResult::path (figures).
  bool record_path = false;
};
// The values each option accepts (validate() and the [placement] keys).
namespace run_range {
inline constexpr common::Range target_icn = common::Range::above_up_to(0.0, 1.0);
// 0 evaluates the start only (the random and URA baselines); a configured run needs >= 1.
inline constexpr common::Range max_iterations = common::Range::closed(0, 10'000'000);
inline constexpr common::Range noise_variance = common::Range::above(0.0);
}  // namespace run_range
void validate(const RunOptions& options);

struct IterationRecord {
  int iteration = 0;     // 0 is the start
  double icn = 0.0;      // of the master's Gram matrix (measured CSI): the stop test's
  double icn_los = 0.0;  // of the LoS channel at the true positions: the milestones' (= icn
                         // without channel conditions)
  double objective = 0.0;
  double placement_dist_m = 0.0;  // mean per UAV, cumulative
  double probe_dist_m = 0.0;      // mean per UAV, cumulative
  double sinr_nv_db = 0.0;        // stream 1, only with RunOptions::trace_sinr
  double sinr_zf_db = 0.0;
  double sinr_mf_db = 0.0;
};

// When the ICN first reached a threshold (reached == false: never within the run).
struct Milestone {
  bool reached = false;
  int iteration = -1;
  // Mean per UAV at that iteration: placement distance, plus probe distance with
  // RunOptions::milestone_distance_includes_probes.
  double placement_dist_m = 0.0;
};

struct RunResult {
  std::string planner;
  RunStatus status = RunStatus::kIterationCap;
  int iterations = 0;  // iterations run (the faulted one included)
  // Iteration 0 (the start) .. iterations. After kNumericalFault the faulted iteration is not
  // recorded (its channel is not finite): the trace ends at iterations - 1.
  std::vector<IterationRecord> trace;
  // kUavUnresponsive and kNumericalFault: what went wrong, e.g. "UAV 7: channel row is
  // non-finite (H(7, 2) = nan) at iteration 40"; empty otherwise.
  std::string fault;
  int fault_uav = -1;  // the UAV the fault names, -1 for none
  Milestone icn050;
  Milestone icn095;
  Eigen::Matrix3Xd start_m;
  Eigen::Matrix3Xd final_m;
  Eigen::VectorXd placement_dist_m;  // per UAV (RunOptions::distance)
  Eigen::VectorXd probe_dist_m;      // per UAV
  // With RunOptions::record_path: the true positions at every trace entry (iteration 0 is
  // start_m; without a fault the last is final_m), one 3 x Nr matrix each; empty otherwise.
  std::vector<Eigen::Matrix3Xd> path;
  bool converged() const { return status == RunStatus::kConverged; }
  bool faulted() const { return status == RunStatus::kUavUnresponsive || status == RunStatus::kNumericalFault; }
};

// Runs the planner until the ICN reaches the target, the iteration cap, or a fault. Health,
// after start() and after every iterate(), before the ICN is evaluated (O(Nr Nt + Nt^2)):
//  1. the planner's fault() (e.g. the closed loop's unresponsive UAV or non-finite belief);
//  2. Swarm::numerical_fault(): the first non-finite commanded move (the Swarm refused it);
//  3. check_finite(swarm): true positions, channel rows and Gram matrix all finite.
// The first of these found ends the run with its status; a fault wins over convergence in the
// same iteration. Runs without a fault are unchanged by these checks.
RunResult run_placement(Planner& planner, Swarm& swarm, const RunOptions& options);

// The first non-finite quantity of the swarm, or nullopt: a true position (UAV m, "position
// is non-finite (q = (...))"), a channel row ("channel row is non-finite (H(m, k) = ...)") or,
// with every row finite, a Gram entry (uav -1). status is kNumericalFault.
std::optional<PlannerFault> check_finite(const Swarm& swarm);

// ICN from a Gram matrix G = H^H H (or K = H H^H): sqrt(lambda_min / lambda_max); 0 when
// num_rows < G.cols() (G = H^H H of a wide H is singular).
// Cheaper than the SVD of H (Nt x Nt eigenproblem) and equal to it above ~1e-6.
double icn_from_gram(const Eigen::MatrixXcd& G, int num_rows);

// icn_below's vectors, kept across calls on a slowly changing G (one run's iterations):
// estimates of the eigenvectors of G's largest and smallest eigenvalues. Empty at first.
struct IcnWarmStart {
  Eigen::VectorXcd top;
  Eigen::VectorXcd bottom;
  int stage0_misses = 0;  // calls since the warm vectors last proved it
};

// true only if ICN(G) < threshold is proven, without an eigen-solve. First (with warm vectors)
// the Rayleigh quotients R(top) <= lambda_max and R(bottom) >= lambda_min: R(bottom) <
// threshold^2 R(top), with a margin far above the rounding error, proves it in two
// matrix-vector products. Else lambda_max >= L (a Rayleigh quotient after two power
// iterations, then if needed the largest Ritz value of 8 Lanczos steps), and lambda_min <
// s = threshold^2 L (less the margin) shown by a failed Cholesky factorisation of G - s I or
// by the smallest Ritz value. false means "not proven" (then use icn_from_gram). warm (optional,
// in/out): a call that tests them advances both vectors by one power step (the bottom one of
// the shifted matrix L I - G), so they follow G from call to call; after 8 calls in a row that
// they did not settle (G changing wholesale) they are tested only every 8th call, and the
// power iterations and Cholesky witness below keep them current meanwhile.
bool icn_below(const Eigen::MatrixXcd& G, int num_rows, double threshold, IcnWarmStart* warm = nullptr);
// The same proof on a swarm's cached Gram matrix, its products by the kernels'
// hermitian_matvec (the dense G is converted only if the products do not settle it).
bool icn_below(const SwarmChannel& channel, double threshold, IcnWarmStart* warm = nullptr);

}  // namespace losmimo::placement
