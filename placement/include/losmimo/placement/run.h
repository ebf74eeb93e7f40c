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

}  // namespace losmimo::placement
