#include "losmimo/fusion/refinement.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <sstream>
#include <stdexcept>

#include "losmimo/placement/common/field_error.h"
#include "losmimo/fusion/cost_functors.h"
#include "solver_options.h"

namespace losmimo::fusion {

namespace {

double dr_sigma_m(const RefinementConfig& c, const Eigen::Vector3d& displacement_m) {
  return c.dr_sigma_floor_m + c.dr_sigma_fraction * displacement_m.norm();
}

// CSI phases are unambiguous only within a lobe: true when the prior's lateral 1-sigma (the
// largest eigenvalue's square root of its y-z block) is at most csi_max_prior_sigma_m.
bool prior_admits_csi(const RefinementConfig& config, const localization::Belief& prior) {
  const Eigen::Matrix2d lateral_cov = prior.cov_m2.bottomRightCorner<2, 2>();
  return std::sqrt(lateral_cov.selfadjointView<Eigen::Lower>().eigenvalues().maxCoeff()) <=
         config.csi_max_prior_sigma_m;
}

// The prior carried forward by dead reckoning: q_i = mean_0 + d_1 + ... + d_i [m] (column i),
// and the newest epoch's covariance cov_0 + sum_i sigma_i^2 I [m^2]. Throws
// std::invalid_argument when an epoch after the first has no displacement_m.
struct DeadReckoning {
  Eigen::Matrix3Xd positions_m;
  Eigen::Matrix3d newest_cov_m2;
};
DeadReckoning dead_reckoning(const RefinementConfig& config, const std::vector<RefinementEpoch>& window) {
  const int num_epochs = static_cast<int>(window.size());
  DeadReckoning dr{Eigen::Matrix3Xd(3, num_epochs), window.front().filter_belief.cov_m2};
  Eigen::Vector3d q_dr = window.front().filter_belief.mean_m;
  for (int i = 0; i < num_epochs; ++i) {
    if (i > 0) {
      if (!window[i].displacement_m) {
        throw std::invalid_argument("refine_window: epoch " + std::to_string(i) +
                                    " has no displacement_m (only the first may lack it)");
      }
      const Eigen::Vector3d& d = *window[i].displacement_m;
      q_dr += d;
      const double sigma = dr_sigma_m(config, d);
      dr.newest_cov_m2 += sigma * sigma * Eigen::Matrix3d::Identity();
    }
    dr.positions_m.col(i) = q_dr;
  }
  return dr;
}

// The prior on q_0, then per epoch i >= 1 its displacement and (if used) its beacon; q_i = q +
// 3 i. Returns the number of beacon blocks added.
int add_prior_motion_and_beacons(ceres::Problem& problem, const RefinementConfig& config,
                                 const std::vector<RefinementEpoch>& window, double* q) {
  problem.AddResidualBlock(
      PositionPriorCost::Create(window.front().filter_belief.mean_m, window.front().filter_belief.cov_m2), nullptr, q);
  int num_beacons = 0;
  for (int i = 1; i < static_cast<int>(window.size()); ++i) {
    const Eigen::Vector3d& d = *window[i].displacement_m;
    problem.AddResidualBlock(DisplacementCost::Create(d, dr_sigma_m(config, d)), nullptr, q + 3 * (i - 1), q + 3 * i);
    if (config.use_beacons && window[i].beacon) {
      const localization::BeaconMeasurement& z = *window[i].beacon;
      problem.AddResidualBlock(BeaconCost::Create(z.range_m, z.azimuth_rad, z.elevation_rad,
                                                  config.beacon_sigma_range_m, config.beacon_sigma_angle_rad),
                               nullptr, q + 3 * i);
      ++num_beacons;
    }
  }
  return num_beacons;
}

// One phase residual block per CSI row, epochs in order, each with its own reference phase
// psi_rad[j] (j counts the rows), started at csi_reference_phase_rad from the initial q_i.
// Throws std::invalid_argument for a row that does not have one entry per BS antenna.
void add_csi_phases(ceres::Problem& problem, const placement::ChannelModel& model, const RefinementConfig& config,
                    const std::vector<RefinementEpoch>& window, double* q, double* psi_rad) {
  const int nt = model.num_antennas();
  const double sigma_phase = csi_phase_sigma_rad(config.csi_noise_variance);
  for (int i = 0; i < static_cast<int>(window.size()); ++i) {
    double* q_i = q + 3 * i;
    const Eigen::Vector3d q_init(q_i[0], q_i[1], q_i[2]);
    for (const CsiMeasurement& csi : window[i].csi) {
      if (csi.y.size() != nt) {
        throw std::invalid_argument("refine_window: a CSI row at epoch " + std::to_string(i) + " has " +
                                    std::to_string(csi.y.size()) + " entries, expected " + std::to_string(nt));
      }
      Eigen::VectorXd phase(nt);
      for (int k = 0; k < nt; ++k) phase(k) = std::arg(csi.y(k));
      *psi_rad = csi_reference_phase_rad(model, csi, q_init);
      problem.AddResidualBlock(
          CsiPhaseCost::Create(phase, model.antennas_m(), model.wavenumber_rad_per_m(), sigma_phase), nullptr, q_i,
          psi_rad);
      ++psi_rad;
    }
  }
}

// The newest position's covariance from the solved problem (DENSE_SVD, single-threaded) into
// cov_m2, symmetrised; false (cov_m2 untouched) when the Jacobian is rank deficient.
bool newest_covariance(ceres::Problem& problem, const RefinementConfig& config, const double* newest_block,
                       Eigen::Matrix3d& cov_m2) {
  ceres::Covariance::Options cov_options;
  cov_options.algorithm_type = ceres::DENSE_SVD;
  cov_options.min_reciprocal_condition_number = config.min_reciprocal_condition_number;
  cov_options.null_space_rank = 0;  // rank deficient -> Compute fails -> false
  cov_options.num_threads = 1;
  ceres::Covariance covariance(cov_options);
  const std::vector<std::pair<const double*, const double*>> blocks = {{newest_block, newest_block}};
  if (!covariance.Compute(blocks, &problem)) return false;
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> cov;
  if (!covariance.GetCovarianceBlock(newest_block, newest_block, cov.data())) return false;
  cov_m2 = 0.5 * (cov + cov.transpose());
  return true;
}

}  // namespace

void validate(const RefinementConfig& c) {
  namespace r = refinement_range;
  const auto require = [](const common::Range& range, double value, const char* field) {
    common::require_field_in(range, value, "refinement", field);
  };
  require(r::window_epochs, c.window_epochs, "window_epochs");
  require(r::positive, c.beacon_sigma_range_m, "beacon_sigma_range_m");
  require(r::positive, c.beacon_sigma_angle_rad, "beacon_sigma_angle_rad");
  require(r::positive, c.dr_sigma_floor_m, "dr_sigma_floor_m");
  require(r::dr_sigma_fraction, c.dr_sigma_fraction, "dr_sigma_fraction");
  require(r::positive, c.csi_noise_variance, "csi_noise_variance");
  require(r::positive, c.csi_max_prior_sigma_m, "csi_max_prior_sigma_m");
  require(r::max_iterations, c.max_iterations, "max_iterations");
  require(r::min_reciprocal_condition_number, c.min_reciprocal_condition_number, "min_reciprocal_condition_number");
}

RefinementConfig refinement_config_from(const localization::NoiseModel& noise, double csi_noise_variance) {
  RefinementConfig c;
  c.beacon_sigma_range_m = noise.sigma_range_m;
  c.beacon_sigma_angle_rad = noise.sigma_angle_rad;
  c.dr_sigma_floor_m = noise.dr_sigma_floor_m;
  c.dr_sigma_fraction = noise.dr_sigma_fraction;
  c.csi_noise_variance = csi_noise_variance;
  validate(c);
  return c;
}

std::string to_string(CovarianceSource source) {
  return source == CovarianceSource::kCeres ? "ceres" : "dead_reckoning";
}

RefinementResult refine_window(const placement::ChannelModel& model, const RefinementConfig& config,
                               const std::vector<RefinementEpoch>& window) {
  validate(config);
  if (window.empty()) throw std::invalid_argument("refine_window: the window is empty");
  const int num_epochs = static_cast<int>(window.size());
  int num_csi_rows = 0;
  for (const RefinementEpoch& e : window) num_csi_rows += static_cast<int>(e.csi.size());
  const bool csi_usable = config.use_csi && prior_admits_csi(config, window.front().filter_belief);

  // Every parameter block lives in one buffer (positions, then one reference phase per CSI
  // row): ceres::Covariance orders blocks by address, so one buffer makes that order, and the
  // covariance's last bits, the same in every process.
  std::vector<double> params(3 * num_epochs + (csi_usable ? num_csi_rows : 0));
  double* const q = params.data();  // q_i = q + 3 i: x, y, z [m]
  // Initial guess and fallback: the prior carried forward by dead reckoning.
  const DeadReckoning dr = dead_reckoning(config, window);
  std::copy(dr.positions_m.data(), dr.positions_m.data() + 3 * num_epochs, q);

  ceres::Problem problem;
  RefinementResult result;
  result.num_epochs = num_epochs;
  result.num_beacons = add_prior_motion_and_beacons(problem, config, window, q);
  result.csi_gated = config.use_csi && !csi_usable && num_csi_rows > 0;
  if (csi_usable) {
    add_csi_phases(problem, model, config, window, q, q + 3 * num_epochs);
    result.num_csi = num_csi_rows;
  }

  const ceres::Solver::Options options = quiet_solver_options(config.max_iterations);
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  result.solver_converged = summary.termination_type == ceres::CONVERGENCE;
  result.iterations = static_cast<int>(summary.iterations.size()) - 1;
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;

  const RefinementEpoch& newest = window.back();
  result.belief.degraded = newest.filter_belief.degraded;
  result.belief.epochs_since_beacon = newest.filter_belief.epochs_since_beacon;
  if (summary.IsSolutionUsable()) {
    result.window_positions_m = Eigen::Map<const Eigen::Matrix3Xd>(q, 3, num_epochs);
  } else {
    result.window_positions_m = dr.positions_m;  // the initial guess
  }
  result.belief.mean_m = result.window_positions_m.col(num_epochs - 1);
  const bool have_covariance =
      summary.IsSolutionUsable() && newest_covariance(problem, config, q + 3 * (num_epochs - 1), result.belief.cov_m2);
  if (!have_covariance) {
    result.covariance_source = CovarianceSource::kDeadReckoning;
    result.belief.cov_m2 = dr.newest_cov_m2;
    result.belief.degraded = true;
  }
  return result;
}

SlidingWindowRefiner::SlidingWindowRefiner(const placement::Scenario& scenario, const RefinementConfig& config)
    : model_(scenario), config_(config) {
  validate(config_);
}

void SlidingWindowRefiner::add_epoch(RefinementEpoch epoch) {
  if (!epoch.displacement_m) window_.clear();
  window_.push_back(std::move(epoch));
  while (static_cast<int>(window_.size()) > config_.window_epochs) window_.pop_front();
}

RefinementResult SlidingWindowRefiner::refine() const {
  if (window_.empty()) throw std::logic_error("SlidingWindowRefiner::refine: no epoch added");
  const std::vector<RefinementEpoch> window(window_.begin(), window_.end());
  return refine_window(model_, config_, window);
}

}  // namespace losmimo::fusion
