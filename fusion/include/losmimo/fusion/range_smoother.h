#pragma once
// Ceres smoothing of a range-only pose track: the pose filters' problem (localization/pose_filter.h,
// a vehicle with robot-frame odometry ranging to mapped beacons) solved over many frames at once,
// seeded by a filter's track. What `losmimo-replay --refine` runs on range-only logs.
//
// Unknowns: one pose x_k = (x_m, y_m, z_m, yaw_rad) per frame (odometry_model.h), map frame.
// Residuals of a problem over frames a..b (pose_cost_functors.h), all whitened:
//   - prior:    the filter's belief at frame a, N(mean, cov) (eigenvalues floored at
//               filter.min_variance_m2). It already holds frame a's ranges and everything
//               before, so frame a's ranges are not used again;
//   - odometry: frames a+1..b, x_k = x_{k-1} (+) (u_k + n), n ~ N(0, Sigma_u), Sigma_u floored as
//               the filters floor it (localization::screen_odometry: the same increment, the
//               same covariance, and a non-finite reading becomes the same in-place prediction);
//   - range:    every reading of frames a+1..b that passes the filters' screen (range_model.h:
//               non-finite / <= 0, unknown beacon ID, outside [min, max]SensorDistance, above
//               filter.max_beacon_range_m; and the geometry check at the seed), with the filters'
//               sigma (range_sigma_m: the scan's stdError or the configured one, floored).
// Outliers: no hard gate. Each range residual r (whitened) has a Cauchy loss whose scale is the
// filters' gate, a = sqrt(range_gate_chi2) sigmas (3.29 by default): rho(r^2) = a^2 log(1 + r^2/a^2),
// quadratic for |r| << a, and its influence falls off beyond a, so a reading the filter would
// gate barely moves the track, while a reading the filter wrongly gated while it was off can
// count again once the track is right. (A Huber loss, linear beyond a, keeps the outliers'
// linear pull: on MRPT's UWB demo, whose ranges hold ~13 % outliers, it smooths worse than the
// filter, 0.36 m RMSE against 0.14 m; docs/range-only.md.) Being non-convex, the Cauchy
// problem needs a good start: the filter's track.
// Modes (window_frames):
//   0      full batch: one problem over the whole log (a = 0, b = last); every frame gets the
//          smoothed pose, i.e. the estimate given all readings, past and future;
//   W >= 2 sliding window: frame k is the newest pose of the problem over frames
//          max(0, k - W + 1)..k (a fixed-lag filter: causal, only past readings).
//   Frame 0 keeps the filter's belief in both.
// Covariance: the marginals of H = J^T J at the solution (J whitened, with Ceres' loss
// corrections, as ceres::Covariance would take it), by chain_marginal_covariances(); where H is
// singular (rank deficiency), the filter's covariance for that frame, counted in
// covariance_fallbacks.
// Deterministic: one thread, same input -> same output.

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "losmimo/placement/common/range.h"
#include "losmimo/localization/pose/filter.h"

namespace losmimo::fusion {

struct RangeSmootherConfig {
  int window_frames = 0;    // 0: full batch over the whole log; else W in [2, 100000]
  int max_iterations = 50;  // Levenberg-Marquardt iterations per problem, in [1, 1000]
};

namespace range_smoother_range {
inline constexpr common::Range window_frames = common::Range::closed(0, 100000);  // and not 1
inline constexpr common::Range max_iterations = common::Range::closed(1, 1000);
}  // namespace range_smoother_range

// Throws common::FieldError naming the first bad field and its value ("range_smoother.window_frames
// = 1: ...").
void validate(const RangeSmootherConfig& config);

// One frame of the track, as the filter saw it.
struct SmootherFrame {
  localization::OdometryIncrement odometry;  // from the previous frame (ignored for frame 0)
  std::vector<localization::BeaconRangeScan> scans;
  localization::PoseBelief filter_belief;  // the filter's belief after this frame: seed and prior
};

struct RangeSmootherResult {
  std::vector<localization::PoseBelief> track;  // one per frame; yaw wrapped to (-pi, pi]
  int problems = 0;                             // Ceres problems solved
  int not_converged = 0;                        // of them, ended without CONVERGENCE (iteration limit, failure)
  std::int64_t iterations = 0;                  // summed over problems
  std::int64_t ranges_used = 0;                 // readings of frames 1.. that passed the screen (each once)
  std::int64_t ranges_down_weighted = 0;        // of them, beyond the loss scale a at the reported pose
  int covariance_fallbacks = 0;
};

// The per-pose blocks of H^-1 for a block-tridiagonal information H (a chain: diagonal blocks
// D_0..D_{n-1}, upper blocks B_i = H_(i, i+1)), in O(n):
//   forward  S_0 = D_0,  S_i = D_i - B_{i-1}^T S_{i-1}^-1 B_{i-1}
//   backward C_{n-1} = S_{n-1}^-1,  C_i = S_i^-1 + G_i C_{i+1} G_i^T,  G_i = S_i^-1 B_i
// (the Rauch-Tung-Striebel recursion in information form). nullopt when some S_i is not
// positive definite or its reciprocal condition number is below 1e-14. Throws
// std::invalid_argument unless upper.size() + 1 == diagonal.size() >= 1.
std::optional<std::vector<Eigen::Matrix4d>> chain_marginal_covariances(const std::vector<Eigen::Matrix4d>& diagonal,
                                                                       const std::vector<Eigen::Matrix4d>& upper);

// Throws std::invalid_argument for an empty track, an invalid config (validate(), and
// localization::validate(PoseFilterConfig)).
RangeSmootherResult smooth_range_track(const localization::PoseFilterConfig& config,
                                       const localization::BeaconMap& beacons, const std::vector<SmootherFrame>& frames,
                                       const RangeSmootherConfig& smoother);

}  // namespace losmimo::fusion
