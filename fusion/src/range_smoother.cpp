#include "losmimo/fusion/range_smoother.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "losmimo/common/field_error.h"
#include "losmimo/fusion/pose_cost_functors.h"
#include "losmimo/localization/beacon_model.h"
#include "losmimo/localization/range_screening.h"

namespace losmimo::fusion {

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
        if (!(localization::range_predict(seed, u.sensor_on_robot_m, u.beacon_m) >= localization::kMinRangeGeometry_m)) {
          continue;
        }
        t.ranges[k].push_back(u);
      }
    }
  }
  return t;
}

// Solves frames a..b and writes the poses of frames report_from..b into out.track.
void solve(const localization::PoseFilterConfig& config, const std::vector<SmootherFrame>& frames,
           const ScreenedTrack& screened, const RangeSmootherConfig& smoother, std::size_t a, std::size_t b,
           std::size_t report_from, RangeSmootherResult& out) {
  const std::size_t n = b - a + 1;
  // One buffer: ceres::Covariance orders blocks by address (see refinement.cpp).
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

  ceres::Solver::Options options;
  options.linear_solver_type = n <= kMaxDensePoses ? ceres::DENSE_QR : ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = smoother.max_iterations;
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ++out.problems;
  if (summary.termination_type != ceres::CONVERGENCE) ++out.not_converged;
  out.iterations += static_cast<std::int64_t>(summary.iterations.size()) - 1;
  const bool usable = summary.IsSolutionUsable();
  if (!usable) {
    for (std::size_t i = 0; i < n; ++i) x[i] = frames[a + i].filter_belief.mean;
  }

  std::vector<std::pair<const double*, const double*>> blocks;
  for (std::size_t k = report_from; k <= b; ++k) blocks.emplace_back(x[k - a].data(), x[k - a].data());
  ceres::Covariance::Options cov_options;
  cov_options.algorithm_type = ceres::SPARSE_QR;
  cov_options.num_threads = 1;
  ceres::Covariance covariance(cov_options);
  const bool have_covariance = usable && covariance.Compute(blocks, &problem);
  for (std::size_t k = report_from; k <= b; ++k) {
    localization::PoseBelief& belief = out.track[k];
    belief = frames[k].filter_belief;
    belief.mean = x[k - a];
    belief.mean(localization::kPoseYaw) = localization::wrap_angle_rad(belief.mean(localization::kPoseYaw));
    Eigen::Matrix<double, 4, 4, Eigen::RowMajor> cov;
    if (have_covariance && covariance.GetCovarianceBlock(x[k - a].data(), x[k - a].data(), cov.data()) &&
        cov.allFinite()) {
      belief.cov = 0.5 * (cov + cov.transpose());
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
                                       const localization::BeaconMap& beacons,
                                       const std::vector<SmootherFrame>& frames,
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
      for (std::size_t k = 1; k <= last; ++k) solve(config, frames, screened, smoother, k + 1 > w ? k + 1 - w : 0, k, k, out);
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
