#include "losmimo/fusion/refinement.h"

#include <ceres/ceres.h>

#include <array>
#include <cmath>
#include <complex>
#include <sstream>
#include <stdexcept>

#include "losmimo/common/field_error.h"
#include "losmimo/fusion/cost_functors.h"
#include "solver_options.h"

namespace losmimo::fusion {

namespace {

double dr_sigma_m(const RefinementConfig& c, const Eigen::Vector3d& displacement_m) {
  return c.dr_sigma_floor_m + c.dr_sigma_fraction * displacement_m.norm();
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

RefinementConfig refinement_config_from(const localization::NoiseModel& noise,
                                        double csi_noise_variance) {
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
  const int nt = model.num_antennas();

  int num_csi_rows = 0;
  for (const RefinementEpoch& e : window) num_csi_rows += static_cast<int>(e.csi.size());
  const Eigen::Matrix2d lateral_cov = window.front().filter_belief.cov_m2.bottomRightCorner<2, 2>();
  const bool csi_usable =
      config.use_csi && std::sqrt(lateral_cov.selfadjointView<Eigen::Lower>().eigenvalues().maxCoeff()) <=
                            config.csi_max_prior_sigma_m;

  // Every parameter block lives in one buffer (positions, then one reference phase per CSI
  // row): ceres::Covariance orders blocks by address, so one buffer makes that order, and the
  // covariance's last bits, the same in every process.
  std::vector<double> params(3 * num_epochs + (csi_usable ? num_csi_rows : 0));
  const auto q_block = [&](int i) { return params.data() + 3 * i; };
  // Initial guess and fallback: the prior carried forward by dead reckoning.
  struct QView {
    double* p;
    double& operator[](int k) const { return p[k]; }
    double* data() const { return p; }
  };
  std::vector<QView> q;
  for (int i = 0; i < num_epochs; ++i) q.push_back({q_block(i)});
  Eigen::Vector3d q_dr = window.front().filter_belief.mean_m;
  Eigen::Matrix3d cov_dr = window.front().filter_belief.cov_m2;
  for (int i = 0; i < num_epochs; ++i) {
    if (i > 0) {
      if (!window[i].displacement_m) {
        throw std::invalid_argument("refine_window: epoch " + std::to_string(i) +
                                    " has no displacement_m (only the first may lack it)");
      }
      const Eigen::Vector3d& d = *window[i].displacement_m;
      q_dr += d;
      const double sigma = dr_sigma_m(config, d);
      cov_dr += sigma * sigma * Eigen::Matrix3d::Identity();
    }
    q[i][0] = q_dr.x();
    q[i][1] = q_dr.y();
    q[i][2] = q_dr.z();
  }

  ceres::Problem problem;
  RefinementResult result;
  result.num_epochs = num_epochs;
  problem.AddResidualBlock(PositionPriorCost::Create(window.front().filter_belief.mean_m,
                                                     window.front().filter_belief.cov_m2),
                           nullptr, q[0].data());
  for (int i = 1; i < num_epochs; ++i) {
    const Eigen::Vector3d& d = *window[i].displacement_m;
    problem.AddResidualBlock(DisplacementCost::Create(d, dr_sigma_m(config, d)), nullptr,
                             q[i - 1].data(), q[i].data());
    if (config.use_beacons && window[i].beacon) {
      const localization::BeaconMeasurement& z = *window[i].beacon;
      problem.AddResidualBlock(BeaconCost::Create(z.range_m, z.azimuth_rad, z.elevation_rad,
                                                  config.beacon_sigma_range_m,
                                                  config.beacon_sigma_angle_rad),
                               nullptr, q[i].data());
      ++result.num_beacons;
    }
  }

  result.csi_gated = config.use_csi && !csi_usable && num_csi_rows > 0;
  if (csi_usable) {
    double* psi_rad = params.data() + 3 * num_epochs;
    const double sigma_phase = csi_phase_sigma_rad(config.csi_noise_variance);
    for (int i = 0; i < num_epochs; ++i) {
      const Eigen::Vector3d q_init(q[i][0], q[i][1], q[i][2]);
      for (const CsiMeasurement& csi : window[i].csi) {
        if (csi.y.size() != nt) {
          throw std::invalid_argument("refine_window: a CSI row at epoch " + std::to_string(i) +
                                      " has " + std::to_string(csi.y.size()) +
                                      " entries, expected " + std::to_string(nt));
        }
        Eigen::VectorXd phase(nt);
        for (int k = 0; k < nt; ++k) phase(k) = std::arg(csi.y(k));
        *psi_rad = csi_reference_phase_rad(model, csi, q_init);
        problem.AddResidualBlock(CsiPhaseCost::Create(phase, model.antennas_m(),
                                                      model.wavenumber_rad_per_m(), sigma_phase),
                                 nullptr, q[i].data(), psi_rad);
        ++psi_rad;
      }
    }
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
  result.window_positions_m.resize(3, num_epochs);
  if (summary.IsSolutionUsable()) {
    for (int i = 0; i < num_epochs; ++i) {
      result.window_positions_m.col(i) << q[i][0], q[i][1], q[i][2];
    }
  } else {
    // Keep the initial guess: the prior carried forward by dead reckoning.
    Eigen::Vector3d qi = window.front().filter_belief.mean_m;
    for (int i = 0; i < num_epochs; ++i) {
      if (i > 0) qi += *window[i].displacement_m;
      result.window_positions_m.col(i) = qi;
    }
  }
  result.belief.mean_m = result.window_positions_m.col(num_epochs - 1);

  bool have_covariance = false;
  if (summary.IsSolutionUsable()) {
    ceres::Covariance::Options cov_options;
    cov_options.algorithm_type = ceres::DENSE_SVD;
    cov_options.min_reciprocal_condition_number = config.min_reciprocal_condition_number;
    cov_options.null_space_rank = 0;  // rank deficient -> Compute fails -> fallback below
    cov_options.num_threads = 1;
    ceres::Covariance covariance(cov_options);
    const double* newest_block = q[num_epochs - 1].data();
    const std::vector<std::pair<const double*, const double*>> blocks = {
        {newest_block, newest_block}};
    if (covariance.Compute(blocks, &problem)) {
      Eigen::Matrix<double, 3, 3, Eigen::RowMajor> cov;
      have_covariance = covariance.GetCovarianceBlock(newest_block, newest_block, cov.data());
      if (have_covariance) result.belief.cov_m2 = 0.5 * (cov + cov.transpose());
    }
  }
  if (!have_covariance) {
    result.covariance_source = CovarianceSource::kDeadReckoning;
    result.belief.cov_m2 = cov_dr;
    result.belief.degraded = true;
  }
  return result;
}

SlidingWindowRefiner::SlidingWindowRefiner(const placement::Scenario& scenario,
                                           const RefinementConfig& config)
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
