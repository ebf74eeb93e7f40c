#include "losmimo/placement/common/seed.h"
#include "losmimo/fusion/closed_loop.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <complex>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/position/initial_belief.h"
#include "losmimo/localization/position/robustness.h"

namespace losmimo::fusion {

namespace {

enum class Stream : std::uint64_t { kSwarm = 1, kSimulator = 2, kFilter = 3, kCsi = 4 };

// A per-UAV stream of the run: common/seed.h with salt 0 (the recorded missions' seeds).
std::uint64_t derive_seed(std::uint64_t run_seed, Stream stream, int uav) {
  const std::uint64_t tag = (static_cast<std::uint64_t>(stream) << 32) | static_cast<std::uint32_t>(uav);
  return common::derive_seed(run_seed, {tag}, 0);
}

}  // namespace

// Everything one UAV owns: its sensors, filter, refiner and CSI generator, each seeded.
struct ClosedLoopPlanner::Uav {
  localization::SensorSimulator simulator;
  UavEstimator estimator;
  std::mt19937_64 csi_rng;
  Eigen::Vector3d last_q_m = Eigen::Vector3d::Zero();  // true position at the last epoch
  double bf_step_scale = 1.0;                          // BF's compass factor (bf.h)
};

ClosedLoopPlanner::ClosedLoopPlanner(const placement::Scenario& scenario, const placement::GdOptions& gd,
                                     const placement::BfOptions& bf, const ClosedLoopConfig& config, std::uint64_t seed)
    : scenario_(scenario),
      gd_options_(gd),
      bf_options_(bf),
      config_(config),
      seed_(seed),
      model_(scenario),
      gd_(scenario, gd),
      stall_(gd.stall_window, gd.stall_min_decrease) {
  placement::validate(bf_options_);
  validate(config_);
}

ClosedLoopPlanner::~ClosedLoopPlanner() = default;

std::string ClosedLoopPlanner::name() const {
  std::string n = "gd+" + std::string(config_.filter_kind == localization::FilterKind::kEkf ? "ekf" : "pf");
  if (config_.refine) n += "+ceres";
  if (config_.gd_mode == GdBeliefMode::kSigmaPoints) n += "+sp";
  return n;
}

void ClosedLoopPlanner::start(placement::Swarm& swarm) {
  const int nr = swarm.num_uavs();
  require_uavs_in_swarm(config_, nr);  // the swarm's size is known only here
  uavs_.clear();
  beliefs_.assign(nr, localization::Belief{});
  heard_.assign(nr, 0);
  silent_since_.assign(nr, 0);
  fault_.reset();
  placed_errors_ = {};
  placed_shape_ = {};
  filter_errors_ = {};
  beacon_only_errors_ = {};
  modes_ = ClosedLoopStats{};
  modes_.gd_iterations.assign(nr, 0);
  modes_.bf_fallback_iterations.assign(nr, 0);
  modes_.last_fallback_iteration.assign(nr, 0);
  modes_.rejected_beacons.assign(nr, 0);
  modes_.rejected_displacements.assign(nr, 0);
  modes_.rejected_csi.assign(nr, 0);
  modes_.silent_iterations.assign(nr, 0);
  stall_.reset();
  escape_rank_ = 0;

  if (observer_) {
    std::vector<std::uint64_t> filter_seeds(nr);
    for (int m = 0; m < nr; ++m) filter_seeds[m] = derive_seed(seed_, Stream::kFilter, m);
    observer_->on_start(filter_seeds);
  }
  const localization::Belief prior = localization::start_cube_prior(scenario_, config_.filter);
  const EstimatorConfig estimator{config_.filter_kind, config_.filter, config_.refine, config_.refinement};
  for (int m = 0; m < nr; ++m) {
    localization::SimulatorConfig sim = config_.simulator;
    for (const UavBeaconOutage& o : config_.outages) {
      if (o.uav == m) sim.outages.push_back(o.window);
    }
    Uav uav{localization::SensorSimulator(sim, derive_seed(seed_, Stream::kSimulator, m)),
            UavEstimator(scenario_, estimator, prior, derive_seed(seed_, Stream::kFilter, m)),
            std::mt19937_64(derive_seed(seed_, Stream::kCsi, m)), swarm.true_positions_m().col(m), 1.0};
    const Eigen::Vector3d q = uav.last_q_m;
    // Epoch 0 belongs to iteration 1: a UAV unresponsive from iteration 1 delivers nothing.
    const bool silent = unresponsive(m, 1);
    heard_[m] = silent ? 0 : 1;
    EpochMeasurements in;
    if (!silent) in.beacon = uav.simulator.measure_beacon(q, 0);
    if (in.beacon && fault_active(UavFaultKind::kNanBeacon, m, 1))
      in.beacon->range_m = std::numeric_limits<double>::quiet_NaN();
    if (config_.refine) in.csi = measure_csi(m, q, 1, uav.csi_rng);
    const EpochEstimate est = uav.estimator.start(std::move(in));
    record_epoch(m, 0, q, est);
    uavs_.push_back(std::move(uav));
  }
  modes_.num_epochs = 1;
  if (!fault_) record_shape(swarm);
}

void ClosedLoopPlanner::record_shape(const placement::Swarm& swarm) {
  Eigen::Matrix3Xd means(3, swarm.num_uavs());
  std::vector<Eigen::Matrix2d> lateral_cov_m2(static_cast<std::size_t>(swarm.num_uavs()));
  for (int m = 0; m < swarm.num_uavs(); ++m) {
    means.col(m) = beliefs_[m].mean_m;
    lateral_cov_m2[static_cast<std::size_t>(m)] = beliefs_[m].cov_m2.bottomRightCorner<2, 2>();
  }
  placed_shape_.add(swarm.true_positions_m(), means, lateral_cov_m2);
}

void ClosedLoopPlanner::localize(placement::Swarm& swarm, int epoch) {
  const int iteration = epoch + 1;
  for (int m = 0; m < swarm.num_uavs(); ++m) {
    if (unresponsive(m, iteration)) continue;  // nothing arrives; the belief stays as it was
    heard_[m] = 1;                             // a reading arrived, finite or not
    Uav& uav = uavs_[m];
    const Eigen::Vector3d q = swarm.true_positions_m().col(m);
    EpochMeasurements in;
    in.displacement_m = uav.simulator.measure_displacement(q - uav.last_q_m);
    uav.last_q_m = q;
    in.beacon = uav.simulator.measure_beacon(q, epoch);
    if (fault_active(UavFaultKind::kNanDisplacement, m, iteration))
      in.displacement_m->x() = std::numeric_limits<double>::quiet_NaN();
    if (in.beacon && fault_active(UavFaultKind::kNanBeacon, m, iteration))
      in.beacon->range_m = std::numeric_limits<double>::quiet_NaN();
    if (config_.refine) in.csi = measure_csi(m, q, iteration, uav.csi_rng);
    const EpochEstimate est = uav.estimator.step(std::move(in));
    record_epoch(m, epoch, q, est);
    if (fault_) return;  // a non-finite belief: no placement
  }
  ++modes_.num_epochs;
  record_shape(swarm);
}

void ClosedLoopPlanner::record_epoch(int m, int epoch, const Eigen::Vector3d& q_m, const EpochEstimate& est) {
  beliefs_[m] = est.belief;
  if (est.rejected_beacon) ++modes_.rejected_beacons[m];
  if (est.rejected_displacement) ++modes_.rejected_displacements[m];
  modes_.rejected_csi[m] += est.rejected_csi;
  if (est.refinement_covariance_fallback) ++modes_.refinement_covariance_fallbacks;
  if (est.health_problem && !fault_) {
    fault_ = placement::PlannerFault{
        placement::RunStatus::kNumericalFault, m,
        "UAV " + std::to_string(m) + ": " + *est.health_problem + " at epoch " + std::to_string(epoch)};
  }
  // A belief that ended the run after epoch 0 is neither observed nor scored; at epoch 0 the
  // run ends before any placement, and every UAV's start is still scored.
  if (fault_ && epoch > 0) return;
  if (est.beacon_fix_m) beacon_only_errors_.add(*est.beacon_fix_m, q_m);
  if (observer_) {
    std::optional<CsiMeasurement> csi;
    if (!est.csi.empty()) csi = est.csi.front();
    observer_->on_epoch({epoch, m, q_m, est.displacement_m, est.beacon, csi, est.filter_belief, est.belief});
  }
  placed_errors_.add(est.belief, q_m);
  filter_errors_.add(est.filter_belief, q_m);
}

bool ClosedLoopPlanner::fault_active(UavFaultKind kind, int m, int iteration) const {
  for (const UavFault& f : config_.faults) {
    if (f.kind == kind && f.uav == m && f.active(iteration)) return true;
  }
  return false;
}

std::vector<CsiMeasurement> ClosedLoopPlanner::measure_csi(int m, const Eigen::Vector3d& q_m, int iteration,
                                                           std::mt19937_64& rng) const {
  std::vector<CsiMeasurement> csi;
  if (!config_.refinement.use_csi) return csi;
  CsiMeasurement row = simulate_csi(model_, q_m, scenario_.noise_variance(), rng);
  if (fault_active(UavFaultKind::kNanCsi, m, iteration) && row.y.size() > 0)
    row.y(0) = std::complex<double>(std::numeric_limits<double>::quiet_NaN(), 0.0);
  csi.push_back(std::move(row));
  return csi;
}

void ClosedLoopPlanner::watch_uavs(int iteration) {
  for (std::size_t m = 0; m < heard_.size(); ++m) {
    if (heard_[m]) {
      silent_since_[m] = 0;
    } else {
      ++modes_.silent_iterations[m];
      if (silent_since_[m] == 0) silent_since_[m] = iteration;
      const int silent = iteration - silent_since_[m] + 1;
      if (!fault_ && silent >= config_.unresponsive_after_iterations) {
        fault_ = placement::PlannerFault{placement::RunStatus::kUavUnresponsive, static_cast<int>(m),
                                         "UAV " + std::to_string(m) + ": no measurement and no motion for " +
                                             std::to_string(silent) + " iteration" + (silent == 1 ? "" : "s") +
                                             " (since iteration " + std::to_string(silent_since_[m]) + ")"};
      }
    }
    heard_[m] = 0;
  }
}

Eigen::Vector3d ClosedLoopPlanner::plan_gd(const placement::Swarm& swarm, int m, int iteration) const {
  const localization::Belief& b = beliefs_[m];
  if (config_.gd_mode == GdBeliefMode::kMean) return gd_.plan_move(swarm, m, b.mean_m, iteration);
  // Unscented points with kappa = 0 for n = 3: the centre has weight 0, the six others 1/6.
  const Eigen::LLT<Eigen::Matrix3d> llt(b.cov_m2);
  if (llt.info() != Eigen::Success) return gd_.plan_move(swarm, m, b.mean_m, iteration);
  const Eigen::Matrix3d spread = std::sqrt(3.0) * llt.matrixL().toDenseMatrix();
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  for (int j = 0; j < 3; ++j) {
    r += gd_.plan_move(swarm, m, b.mean_m + spread.col(j), iteration);
    r += gd_.plan_move(swarm, m, b.mean_m - spread.col(j), iteration);
  }
  return r / 6.0;
}

void ClosedLoopPlanner::iterate(placement::Swarm& swarm, int iteration) {
  if (uavs_.size() != static_cast<std::size_t>(swarm.num_uavs()))
    throw std::logic_error("ClosedLoopPlanner::iterate before start()");
  if (fault_) return;
  if (iteration > 1) localize(swarm, iteration - 1);  // epoch 0 was start()'s (heard_ set there)
  if (fault_) return;                                 // a non-finite belief never reaches placement
  escape_iteration_ = iteration;

  const double b_bf = bf_options_.step * std::pow(bf_options_.decay, iteration - 1);
  std::string modes(swarm.num_uavs(), static_cast<char>(UavMode::kGd));
  for (int m = 0; m < swarm.num_uavs(); ++m) {
    if (unresponsive(m, iteration)) {  // the command is lost: the UAV hovers where it is
      modes[m] = '-';
      continue;
    }
    const Eigen::Vector3d q_before = swarm.true_positions_m().col(m);
    Eigen::Vector3d commanded = Eigen::Vector3d::Zero();
    if (config_.fallback_to_bf && beliefs_[m].degraded) {
      Uav& uav = uavs_[m];
      const double b_m = std::max(b_bf * uav.bf_step_scale, std::min(b_bf, bf_options_.min_step_m));
      const int probe = placement::BruteForcePlanner::step_uav(swarm, m, b_m);
      const bool moved = probe != 0;
      if (observer_) commanded = b_m * placement::bf_probe_direction(probe);
      uav.bf_step_scale = moved ? std::min(1.0, uav.bf_step_scale / bf_options_.contraction)
                                : uav.bf_step_scale * bf_options_.contraction;
      modes[m] = static_cast<char>(UavMode::kBf);
      ++modes_.bf_fallback_iterations[m];
      modes_.last_fallback_iteration[m] = iteration;
    } else {
      // Back in GD the compass restarts from the full step at the next fallback.
      uavs_[m].bf_step_scale = 1.0;
      commanded = plan_gd(swarm, m, iteration);
      swarm.move(m, commanded, placement::MotionKind::kPlacement);
      ++modes_.gd_iterations[m];
    }
    if (swarm.true_positions_m().col(m) != q_before) heard_[m] = 1;
    if (observer_) {
      observer_->on_move(
          {iteration, m, static_cast<UavMode>(modes[m]), false, commanded, swarm.true_positions_m().col(m) - q_before});
    }
  }
  modes_.mode_trace.push_back(modes);
  if (gd_options_.escape && stall_.update(swarm.channel().objective()) && try_escape(swarm)) {
    stall_.reset();
    ++modes_.escapes;
  }
  watch_uavs(iteration);
  if (observer_) observer_->on_iteration_end(iteration, swarm);
}

// GradientDescentPlanner's escape (gd.h), from the belief mean; BF-mode UAVs are skipped.
bool ClosedLoopPlanner::try_escape(placement::Swarm& swarm) {
  const std::vector<int> order = placement::uavs_by_redundancy(swarm.channel());
  const int m = order[escape_rank_ % static_cast<int>(order.size())];
  ++escape_rank_;
  if (config_.fallback_to_bf && beliefs_[m].degraded) return false;
  if (unresponsive(m, escape_iteration_)) return false;  // it would not fly the escape
  const Eigen::Vector3d q_hat = beliefs_[m].mean_m;
  const placement::LateralSearch search = placement::search_lateral_period(
      placement::UavObjective(swarm.channel(), m), q_hat,
      placement::lateral_period_m(scenario_.wavelength_m(), q_hat.x(), scenario_.bs_spacing_m));
  const Eigen::Vector3d& best_offset = search.offset_m;
  if (search.best_objective < (1.0 - gd_options_.stall_min_decrease) * search.objective_at_start) {
    const Eigen::Vector3d q_before = swarm.true_positions_m().col(m);
    swarm.move(m, best_offset, placement::MotionKind::kPlacement);
    if (observer_) {
      observer_->on_move(
          {escape_iteration_, m, UavMode::kGd, true, best_offset, swarm.true_positions_m().col(m) - q_before});
    }
    escape_rank_ = 0;
    return true;
  }
  return false;
}

ClosedLoopStats ClosedLoopPlanner::stats() const {
  ClosedLoopStats s = modes_;
  if (placed_errors_.samples() > 0) {
    s.rmse_m = placed_errors_.rmse_m();
    s.lateral_rmse_m = placed_errors_.lateral_rmse_m();
    s.average_nees = placed_errors_.average_nees();
    s.filter_rmse_m = filter_errors_.rmse_m();
    s.filter_lateral_rmse_m = filter_errors_.lateral_rmse_m();
    s.filter_average_nees = filter_errors_.average_nees();
  }
  if (placed_shape_.epochs() > 0) {
    s.common_lateral_rms_m = placed_shape_.common_lateral_rms_m();
    s.shape_lateral_rmse_m = placed_shape_.shape_lateral_rmse_m();
    s.shape_nees_per_dof = placed_shape_.shape_nees_per_dof();
  }
  s.num_beacons = static_cast<int>(beacon_only_errors_.samples());
  if (beacon_only_errors_.samples() > 0) {
    s.beacon_only_rmse_m = beacon_only_errors_.rmse_m();
    s.beacon_only_lateral_rmse_m = beacon_only_errors_.lateral_rmse_m();
  }
  return s;
}

ClosedLoopRun run_closed_loop(const placement::PlacementSettings& settings, const Eigen::Matrix3Xd& start_m,
                              const ClosedLoopConfig& config, std::uint64_t seed, ClosedLoopObserver* observer) {
  placement::ErrorModel errors = settings.errors;
  errors.clear_localization();                             // the beliefs replace the Gaussian localization model
  const placement::ChannelModel model(settings.scenario);  // the Swarm keeps a pointer to it
  placement::Swarm swarm(model, start_m, errors, derive_seed(seed, Stream::kSwarm, 0));
  ClosedLoopPlanner planner(settings.scenario, settings.gd, settings.bf, config, seed);
  planner.set_observer(observer);
  ClosedLoopRun out;
  out.run = placement::run_placement(planner, swarm, placement::with_override(settings.run, settings.gd_run));
  out.stats = planner.stats();
  return out;
}

}  // namespace losmimo::fusion
