#include "losmimo/fusion/range_smoother.h"

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "losmimo/placement/common/field_error.h"
#include "losmimo/fusion/pose_cost_functors.h"
#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/pose/robustness.h"
#include "solver_options.h"

namespace losmimo::fusion {

// Below this reciprocal condition number a block of the chain's elimination counts as singular.
constexpr double kMinReciprocalCondition = 1e-14;

std::optional<std::vector<Eigen::Matrix4d>> chain_marginal_covariances(const std::vector<Eigen::Matrix4d>& diagonal,
                                                                       const std::vector<Eigen::Matrix4d>& upper) {
  const std::size_t n = diagonal.size();
  if (n == 0 || upper.size() + 1 != n) throw std::invalid_argument("chain_marginal_covariances: block counts differ");
  // Forward: S_i and S_i^-1.
  std::vector<Eigen::Matrix4d> S_inv(n);
  Eigen::Matrix4d S = diagonal[0];
  for (std::size_t i = 0;; ++i) {
    const Eigen::LLT<Eigen::Matrix4d> llt(S);
    if (llt.info() != Eigen::Success || !(llt.rcond() >= kMinReciprocalCondition)) return std::nullopt;
    S_inv[i] = llt.solve(Eigen::Matrix4d::Identity());
    if (i + 1 == n) break;
    S = diagonal[i + 1] - upper[i].transpose() * S_inv[i] * upper[i];
  }
  // Backward: C_i = S_i^-1 + G_i C_{i+1} G_i^T, G_i = S_i^-1 B_i.
  std::vector<Eigen::Matrix4d> C(n);
  C[n - 1] = S_inv[n - 1];
  for (std::size_t i = n - 1; i-- > 0;) {
    const Eigen::Matrix4d G = S_inv[i] * upper[i];
    C[i] = S_inv[i] + G * C[i + 1] * G.transpose();
  }
  for (Eigen::Matrix4d& c : C) c = (0.5 * (c + c.transpose())).eval();
  return C;
}

namespace {

using localization::UsableRange;
using Pose = Eigen::Vector4d;

// Problems up to this many poses use dense QR; longer ones sparse Cholesky.
constexpr int kMaxDensePoses = 16;

// What the smoother uses of a track: per frame the filters' odometry noise and screened readings.
struct ScreenedTrack {
  std::vector<localization::OdometryIncrement> odometry;
  std::vector<std::vector<UsableRange>> ranges;
};

ScreenedTrack screen_track(const localization::PoseFilterConfig& config, const localization::BeaconMap& beacons,
                           const std::vector<SmootherFrame>& frames) {
  ScreenedTrack t;
  t.odometry.resize(frames.size());
  t.ranges.resize(frames.size());
  localization::FilterCounters counted_by_the_filter;  // the filter reports the counts already
  for (std::size_t k = 1; k < frames.size(); ++k) {
    t.odometry[k] = localization::screen_odometry(config, frames[k].odometry, counted_by_the_filter);
    const Pose& seed = frames[k].filter_belief.mean;
    for (const localization::BeaconRangeScan& scan : frames[k].scans) {
      const double sigma_m = localization::range_sigma_m(config, scan);
      for (const localization::BeaconRange& r : scan.ranges) {
        if (localization::screen_range(r, scan, beacons, sigma_m, config.filter.max_beacon_range_m) !=
            localization::RangeVerdict::kUsable) {
          continue;
        }
        const UsableRange u{*beacons.find(r.beacon_id), r.sensor_on_robot_m, r.range_m, sigma_m};
        if (!(localization::range_predict(seed, u.sensor_on_robot_m, u.beacon_m) >=
              localization::kMinRangeGeometry_m)) {
          continue;
        }
        t.ranges[k].push_back(u);
      }
    }
  }
  return t;
}

// The chain's information at the solution, H = J^T J (J whitened, with Ceres' loss corrections:
// what ceres::Covariance would use), as diagonal and upper off-diagonal blocks, then its marginals.
std::optional<std::vector<Eigen::Matrix4d>> marginals_at_solution(ceres::Problem& problem, std::vector<Pose>& x) {
  const std::size_t n = x.size();
  ceres::Problem::EvaluateOptions eval;
  for (Pose& p : x) eval.parameter_blocks.push_back(p.data());
  eval.apply_loss_function = true;
  eval.num_threads = 1;
  ceres::CRSMatrix J;
  if (!problem.Evaluate(eval, nullptr, nullptr, nullptr, &J)) return std::nullopt;
  std::vector<Eigen::Matrix4d> diagonal(n, Eigen::Matrix4d::Zero());
  std::vector<Eigen::Matrix4d> upper(n > 0 ? n - 1 : 0, Eigen::Matrix4d::Zero());
  for (int row = 0; row < J.num_rows; ++row) {
    for (int i = J.rows[row]; i < J.rows[row + 1]; ++i) {
      for (int j = J.rows[row]; j < J.rows[row + 1]; ++j) {
        const int ci = J.cols[i], cj = J.cols[j];
        const double v = J.values[i] * J.values[j];
        if (ci / 4 == cj / 4) {
          diagonal[static_cast<std::size_t>(ci / 4)](ci % 4, cj % 4) += v;
        } else if (cj / 4 == ci / 4 + 1) {
          upper[static_cast<std::size_t>(ci / 4)](ci % 4, cj % 4) += v;
        }
      }
    }
  }
  return chain_marginal_covariances(diagonal, upper);
}

// Solves frames a..b and writes the poses of frames report_from..b into out.track.
void solve(const localization::PoseFilterConfig& config, const std::vector<SmootherFrame>& frames,
           const ScreenedTrack& screened, const RangeSmootherConfig& smoother, std::size_t a, std::size_t b,
           std::size_t report_from, RangeSmootherResult& out) {
  const std::size_t n = b - a + 1;
  // The poses, seeded by the filter's track.
  std::vector<Pose> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = frames[a + i].filter_belief.mean;

  ceres::Problem problem;
  Eigen::Matrix4d prior_cov = frames[a].filter_belief.cov;
  localization::make_spd(prior_cov, config.filter.min_variance_m2, 1.0);
  problem.AddResidualBlock(PosePriorCost::Create(frames[a].filter_belief.mean, prior_cov), nullptr, x[0].data());
  const double scale = std::sqrt(config.range_gate_chi2);
  for (std::size_t i = 1; i < n; ++i) {
    const localization::OdometryIncrement& u = screened.odometry[a + i];
    problem.AddResidualBlock(OdometryCost::Create(u.delta, u.cov), nullptr, x[i - 1].data(), x[i].data());
    for (const UsableRange& r : screened.ranges[a + i]) {
      problem.AddResidualBlock(RangeCost::Create(r.range_m, r.sensor_on_robot_m, r.beacon_m, r.sigma_m),
                               new ceres::CauchyLoss(scale), x[i].data());
    }
  }

  ceres::Solver::Options options = quiet_solver_options(smoother.max_iterations);
  if (n > kMaxDensePoses) options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  // Eigen's simplicial Cholesky: reproduces its last bit (SuiteSparse, through a multithreaded BLAS,
  // need not).
  options.sparse_linear_algebra_library_type = ceres::EIGEN_SPARSE;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ++out.problems;
  if (summary.termination_type != ceres::CONVERGENCE) ++out.not_converged;
  out.iterations += static_cast<std::int64_t>(summary.iterations.size()) - 1;
  const bool usable = summary.IsSolutionUsable();
  if (!usable) {
    for (std::size_t i = 0; i < n; ++i) x[i] = frames[a + i].filter_belief.mean;
  }

  std::optional<std::vector<Eigen::Matrix4d>> marginals;
  if (usable) marginals = marginals_at_solution(problem, x);
  for (std::size_t k = report_from; k <= b; ++k) {
    localization::PoseBelief& belief = out.track[k];
    belief = frames[k].filter_belief;
    belief.mean = x[k - a];
    belief.mean(localization::kPoseYaw) = localization::wrap_angle_rad(belief.mean(localization::kPoseYaw));
    if (marginals) {
      belief.cov = (*marginals)[k - a];
    } else {
      ++out.covariance_fallbacks;
    }
  }
}

}  // namespace

void validate(const RangeSmootherConfig& c) {
  namespace r = range_smoother_range;
  common::require_field_in(r::window_frames, c.window_frames, "range_smoother", "window_frames");
  if (c.window_frames == 1) {
    throw common::FieldError("window_frames",
                             "range_smoother.window_frames = 1: must be 0 (the whole log) or >= 2 (a window holds "
                             "the prior's frame and at least one more)");
  }
  common::require_field_in(r::max_iterations, c.max_iterations, "range_smoother", "max_iterations");
}

RangeSmootherResult smooth_range_track(const localization::PoseFilterConfig& config,
                                       const localization::BeaconMap& beacons, const std::vector<SmootherFrame>& frames,
                                       const RangeSmootherConfig& smoother) {
  validate(smoother);
  localization::validate(config);
  if (frames.empty()) throw std::invalid_argument("smooth_range_track: no frame");
  const ScreenedTrack screened = screen_track(config, beacons, frames);
  RangeSmootherResult out;
  out.track.resize(frames.size());
  out.track[0] = frames[0].filter_belief;
  const std::size_t last = frames.size() - 1;
  if (last > 0) {
    if (smoother.window_frames == 0) {
      solve(config, frames, screened, smoother, 0, last, 1, out);
    } else {
      const std::size_t w = static_cast<std::size_t>(smoother.window_frames);
      for (std::size_t k = 1; k <= last; ++k)
        solve(config, frames, screened, smoother, k + 1 > w ? k + 1 - w : 0, k, k, out);
    }
  }
  const double scale = std::sqrt(config.range_gate_chi2);
  for (std::size_t k = 1; k <= last; ++k) {
    for (const UsableRange& r : screened.ranges[k]) {
      ++out.ranges_used;
      const double e = r.range_m - localization::range_predict(out.track[k].mean, r.sensor_on_robot_m, r.beacon_m);
      if (!(std::abs(e) <= scale * r.sigma_m)) ++out.ranges_down_weighted;
    }
  }
  return out;
}

}  // namespace losmimo::fusion
