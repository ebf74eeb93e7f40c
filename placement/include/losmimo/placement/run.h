#pragma once
// One placement run: a planner iterates over the swarm (one pass over all UAVs per
// iteration, as the paper's master does) until the ICN reaches the target or the cap.

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "losmimo/placement/swarm.h"

namespace losmimo::placement {

// One distributed placement algorithm (GD, BF, URA, ...).
class Planner {
 public:
  virtual ~Planner() = default;
  virtual std::string name() const = 0;
  // Called once before the first iteration (e.g. the URA assignment).
  virtual void start(Swarm& /*swarm*/) {}
  // One pass over all UAVs; iteration counts from 1.
  virtual void iterate(Swarm& swarm, int iteration) = 0;
};

struct RunOptions {
  double target_icn = 0.95;
  int max_iterations = 1000;
  bool trace_sinr = false;      // per-iteration SINR of stream 1 in the trace (an LLT each)
  double noise_variance = 0.1;  // normalised units (Scenario::noise_variance), for trace_sinr
  // false: an iteration whose ICN is proven (icn_below) below every threshold still pending
  // (0.5 and 0.95 until reached, target_icn) skips the eigen-solve and records icn = NaN in
  // the trace. Milestones, status and iterations are the same either way; the experiment's
  // untraced runs use it (runs under errors spend most iterations far below the target).
  bool full_icn_trace = true;
};
void validate(const RunOptions& options);

struct IterationRecord {
  int iteration = 0;  // 0 is the start
  double icn = 0.0;
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
  double placement_dist_m = 0.0;  // mean per UAV at that iteration
};

enum class RunStatus { kConverged, kIterationCap };
std::string to_string(RunStatus status);

struct RunResult {
  std::string planner;
  RunStatus status = RunStatus::kIterationCap;
  int iterations = 0;
  std::vector<IterationRecord> trace;  // iteration 0 (the start) .. iterations
  Milestone icn050;
  Milestone icn095;
  Eigen::Matrix3Xd start_m;
  Eigen::Matrix3Xd final_m;
  Eigen::VectorXd placement_dist_m;  // per UAV
  Eigen::VectorXd probe_dist_m;      // per UAV
  bool converged() const { return status == RunStatus::kConverged; }
};

RunResult run_placement(Planner& planner, Swarm& swarm, const RunOptions& options);

// ICN from the Gram matrix G = H^H H: sqrt(lambda_min / lambda_max); 0 when Nr < Nt.
// Cheaper than the SVD of H (Nt x Nt eigenproblem) and equal to it above ~1e-6.
double icn_from_gram(const Eigen::MatrixXcd& G, int num_rows);

// true only if ICN(G) < threshold is proven, without an eigen-solve: lambda_max >= L (a
// Rayleigh quotient after two power iterations, then if needed the largest Ritz value of 8
// Lanczos steps), and lambda_min < s = threshold^2 L (less a margin far above the rounding
// error) shown by a failed Cholesky factorisation of G - s I or by the smallest Ritz value.
// false means "not proven" (then use icn_from_gram). warm_start (optional, in/out): the power
// iteration's vector, to pass again at the next, slightly changed G.
bool icn_below(const Eigen::MatrixXcd& G, int num_rows, double threshold,
               Eigen::VectorXcd* warm_start = nullptr);

}  // namespace losmimo::placement
