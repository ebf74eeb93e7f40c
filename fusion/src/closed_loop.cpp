#include "losmimo/common/seed.h"
#include "losmimo/fusion/closed_loop.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <complex>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "losmimo/common/field_error.h"
#include "losmimo/localization/beacon_model.h"
#include "losmimo/localization/robustness.h"

namespace losmimo::fusion {

namespace {

enum class Stream : std::uint64_t { kSwarm = 1, kSimulator = 2, kFilter = 3, kCsi = 4 };

// A per-UAV stream of the run (common/seed.h; salt 0 keeps recorded missions' seeds).
std::uint64_t derive_seed(std::uint64_t run_seed, Stream stream, int uav) {
  const std::uint64_t tag = (static_cast<std::uint64_t>(stream) << 32) | static_cast<std::uint32_t>(uav);
  return common::derive_seed(run_seed, {tag}, 0);
}

[[noreturn]] void fail(const std::string& field, double value, const std::string& rule) {
  std::ostringstream msg;
  msg << "closed_loop." << field << " = " << value << ": must be " << rule;
  throw common::FieldError(field, msg.str());
}

// BruteForcePlanner::step_uav's probe directions (bf.cpp), for the observer's commanded move.
Eigen::Vector3d bf_probe_direction(int probe) {
  static const Eigen::Vector3d kDirections[7] = {
      Eigen::Vector3d(0, 0, 0),  Eigen::Vector3d(1, 0, 0),  Eigen::Vector3d(-1, 0, 0),
      Eigen::Vector3d(0, 1, 0),  Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(0, 0, 1),
      Eigen::Vector3d(0, 0, -1)};
  return probe >= 0 && probe < 7 ? kDirections[probe] : Eigen::Vector3d::Zero();
}

double nees(const localization::Belief& b, const Eigen::Vector3d& truth_m) {
  const Eigen::Vector3d e = b.mean_m - truth_m;
  return e.dot(b.cov_m2.ldlt().solve(e));
}

}  // namespace

std::string to_string(GdBeliefMode mode) {
  return mode == GdBeliefMode::kMean ? "mean" : "sigma_points";
}

GdBeliefMode gd_belief_mode_from_string(const std::string& text) {
  if (text == "mean") return GdBeliefMode::kMean;
  if (text == "sigma_points") return GdBeliefMode::kSigmaPoints;
  throw std::invalid_argument("closed_loop.gd_mode = '" + text + "': must be mean or sigma_points");
}

std::string to_string(UavFaultKind kind) {
  switch (kind) {
    case UavFaultKind::kUnresponsive: return "unresponsive";
    case UavFaultKind::kNanBeacon: return "nan_beacon";
    case UavFaultKind::kNanDisplacement: return "nan_displacement";
    case UavFaultKind::kNanCsi: return "nan_csi";
  }
  return "unknown";
}

UavFaultKind uav_fault_kind_from_string(const std::string& text) {
  for (const UavFaultKind kind : {UavFaultKind::kUnresponsive, UavFaultKind::kNanBeacon,
                                  UavFaultKind::kNanDisplacement, UavFaultKind::kNanCsi}) {
    if (to_string(kind) == text) return kind;
  }
  throw std::invalid_argument("fault kind '" + text +
                              "': must be unresponsive, nan_beacon, nan_displacement or nan_csi");
}

int ClosedLoopStats::rejected_measurements() const {
  int n = 0;
  for (const std::vector<int>* v : {&rejected_beacons, &rejected_displacements, &rejected_csi}) {
    for (const int k : *v) n += k;
  }
  return n;
}

void validate(const ClosedLoopConfig& config) {
  // The truth first: a bad true noise is reported as such, not as the filter's copy of it.
  common::with_field_prefix("simulator", [&] { localization::validate(config.simulator); });
  common::with_field_prefix("filter", [&] { localization::validate(config.filter); });
  common::with_field_prefix("refinement", [&] { validate(config.refinement); });
  if (config.unresponsive_after_iterations < 1 || config.unresponsive_after_iterations > 1000) {
    fail("unresponsive_after_iterations", config.unresponsive_after_iterations, "in [1, 1000]");
  }
  for (std::size_t i = 0; i < config.faults.size(); ++i) {
    const UavFault& f = config.faults[i];
    const std::string field = "faults[" + std::to_string(i) + "]";
    if (f.uav < 0) fail(field + ".uav", f.uav, ">= 0");
    if (f.from_iteration < 1) fail(field + ".from_iteration", f.from_iteration, ">= 1");
    if (f.num_iterations < 0) fail(field + ".num_iterations", f.num_iterations, ">= 0");
    if (f.kind == UavFaultKind::kNanCsi && !(config.refine && config.refinement.use_csi)) {
      throw common::FieldError(field, "closed_loop." + field +
                                          " = nan_csi: needs refine = true and use_csi = true (no CSI "
                                          "is measured otherwise)");
    }
  }
  for (std::size_t i = 0; i < config.outages.size(); ++i) {
    const UavBeaconOutage& o = config.outages[i];
    const std::string field = "outages[" + std::to_string(i) + "]";
    if (o.uav < 0) fail(field + ".uav", o.uav, ">= 0");
    if (o.window.first_epoch < 0) fail(field + ".first_epoch", o.window.first_epoch, ">= 0");
    if (o.window.num_epochs < 0) fail(field + ".num_epochs", o.window.num_epochs, ">= 0");
  }
}

ClosedLoopConfig matched_closed_loop_config(const localization::SimulatorConfig& simulator,
                                            const placement::Scenario& scenario) {
  ClosedLoopConfig config;
  config.simulator = simulator;
  config.filter.noise.sigma_range_m = simulator.sigma_range_m;
  config.filter.noise.sigma_angle_rad = simulator.sigma_angle_rad;
  config.filter.noise.dr_sigma_floor_m = simulator.dr_sigma_floor_m;
  config.filter.noise.dr_sigma_fraction = simulator.dr_sigma_fraction;
  config.refinement = refinement_config_from(config.filter.noise, scenario.noise_variance());
  return config;
}

// Everything one UAV owns: its sensors, filter, refiner and CSI generator, each seeded.
struct ClosedLoopPlanner::Uav {
  localization::SensorSimulator simulator;
  std::unique_ptr<localization::PositionFilter> filter;
  std::optional<SlidingWindowRefiner> refiner;
  std::mt19937_64 csi_rng;
  Eigen::Vector3d last_q_m = Eigen::Vector3d::Zero();  // true position at the last epoch
  double bf_step_scale = 1.0;                          // BF's compass factor (bf.h)
};

ClosedLoopPlanner::ClosedLoopPlanner(const placement::Scenario& scenario,
                                     const placement::GdOptions& gd, const placement::BfOptions& bf,
                                     const ClosedLoopConfig& config, std::uint64_t seed)
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
  for (std::size_t i = 0; i < config_.outages.size(); ++i) {
    if (config_.outages[i].uav >= nr) {
      fail("outages[" + std::to_string(i) + "].uav", config_.outages[i].uav,
           "< the number of UAVs (" + std::to_string(nr) + ")");
    }
  }
  for (std::size_t i = 0; i < config_.faults.size(); ++i) {
    if (config_.faults[i].uav >= nr) {
      fail("faults[" + std::to_string(i) + "].uav", config_.faults[i].uav,
           "< the number of UAVs (" + std::to_string(nr) + ")");
    }
  }
  uavs_.clear();
  beliefs_.assign(nr, localization::Belief{});
  heard_.assign(nr, 0);
  silent_since_.assign(nr, 0);
  fault_.reset();
  sums_ = Sums{};
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
  const double prior_sigma_m = scenario_.cube_side_m / std::sqrt(12.0);  // uniform start cube
  for (int m = 0; m < nr; ++m) {
    localization::SimulatorConfig sim = config_.simulator;
    for (const UavBeaconOutage& o : config_.outages) {
      if (o.uav == m) sim.outages.push_back(o.window);
    }
    Uav uav{localization::SensorSimulator(sim, derive_seed(seed_, Stream::kSimulator, m)),
            nullptr, std::nullopt, std::mt19937_64(derive_seed(seed_, Stream::kCsi, m)),
            swarm.true_positions_m().col(m), 1.0};
    const Eigen::Vector3d q = uav.last_q_m;
    // Epoch 0 belongs to iteration 1: a UAV unresponsive from iteration 1 delivers nothing.
    const bool silent = unresponsive(m, 1);
    std::optional<localization::BeaconMeasurement> z0;
    if (!silent) z0 = uav.simulator.measure_beacon(q, 0);
    if (z0 && fault_active(UavFaultKind::kNanBeacon, m, 1))
      z0->range_m = std::numeric_limits<double>::quiet_NaN();
    // The first fix is taken here, not by the filter, so the filter's plausibility screen
    // (finite, range within max_beacon_range_m, elevation within +-pi/2) is applied here too.
    if (z0 && !localization::is_plausible(config_.filter, *z0)) {
      ++modes_.rejected_beacons[m];
      z0.reset();
    }
    heard_[m] = silent ? 0 : 1;
    localization::Belief initial;
    if (z0) {
      initial = localization::beacon_fix(*z0, config_.filter.noise.sigma_range_m,
                                         config_.filter.noise.sigma_angle_rad);
      sums_.beacon_sq_m2 += (initial.mean_m - q).squaredNorm();
      sums_.beacon_lateral_sq_m2 += (initial.mean_m - q).tail<2>().squaredNorm();
      ++sums_.beacons;
    } else {
      initial.mean_m = scenario_.cube_center_m;
      initial.cov_m2 = prior_sigma_m * prior_sigma_m * Eigen::Matrix3d::Identity();
      initial.degraded = true;
      initial.epochs_since_beacon = config_.filter.degraded_after_epochs;
    }
    if (const std::optional<std::string> problem = localization::health_problem(initial)) {
      // e.g. a fix from an absurd (finite) beacon range: the run ends at iteration 0; the
      // filter, which would refuse such a belief, starts from the prior meanwhile.
      if (!fault_) {
        fault_ = placement::PlannerFault{placement::RunStatus::kNumericalFault, m,
                                         "UAV " + std::to_string(m) + ": initial beacon fix " +
                                             *problem + " at epoch 0"};
      }
      initial.mean_m = scenario_.cube_center_m;
      initial.cov_m2 = prior_sigma_m * prior_sigma_m * Eigen::Matrix3d::Identity();
      initial.degraded = true;
      initial.epochs_since_beacon = config_.filter.degraded_after_epochs;
      z0.reset();
    }
    uav.filter = localization::make_filter(config_.filter_kind, config_.filter, initial,
                                           derive_seed(seed_, Stream::kFilter, m));
    localization::Belief belief = initial;
    std::optional<CsiMeasurement> observed_csi;
    if (config_.refine) {
      uav.refiner.emplace(scenario_, config_.refinement);
      std::vector<CsiMeasurement> csi = measure_csi(m, q, 1, uav.csi_rng);
      if (observer_ && !csi.empty()) observed_csi = csi.front();
      uav.refiner->add_epoch({initial, std::nullopt, z0, std::move(csi)});
      const RefinementResult r = uav.refiner->refine();
      if (r.covariance_source == CovarianceSource::kDeadReckoning) ++modes_.refinement_covariance_fallbacks;
      belief = r.belief;
    }
    beliefs_[m] = belief;
    check_beliefs(m, 0, uav, initial, belief);
    if (observer_) observer_->on_epoch({0, m, q, std::nullopt, z0, observed_csi, initial, belief});
    const Eigen::Vector3d e = belief.mean_m - q, e_f = initial.mean_m - q;
    sums_.sq_m2 += e.squaredNorm();
    sums_.lateral_sq_m2 += e.tail<2>().squaredNorm();
    sums_.nees += nees(belief, q);
    sums_.filter_sq_m2 += e_f.squaredNorm();
    sums_.filter_lateral_sq_m2 += e_f.tail<2>().squaredNorm();
    sums_.filter_nees += nees(initial, q);
    ++sums_.samples;
    uavs_.push_back(std::move(uav));
  }
  modes_.num_epochs = 1;
}

void ClosedLoopPlanner::localize(placement::Swarm& swarm, int epoch) {
  const int iteration = epoch + 1;
  for (int m = 0; m < swarm.num_uavs(); ++m) {
    if (unresponsive(m, iteration)) continue;  // nothing arrives; the belief stays as it was
    heard_[m] = 1;  // a reading arrived, finite or not
    Uav& uav = uavs_[m];
    const Eigen::Vector3d q = swarm.true_positions_m().col(m);
    Eigen::Vector3d d_meas = uav.simulator.measure_displacement(q - uav.last_q_m);
    uav.last_q_m = q;
    std::optional<localization::BeaconMeasurement> z = uav.simulator.measure_beacon(q, epoch);
    // Injected faults, then the master's screening: nothing non-finite or implausible goes further.
    if (fault_active(UavFaultKind::kNanDisplacement, m, iteration))
      d_meas.x() = std::numeric_limits<double>::quiet_NaN();
    if (z && fault_active(UavFaultKind::kNanBeacon, m, iteration))
      z->range_m = std::numeric_limits<double>::quiet_NaN();
    std::optional<Eigen::Vector3d> d_used = d_meas;
    if (!d_meas.allFinite()) {
      ++modes_.rejected_displacements[m];
      d_used.reset();
    }
    // Implausible beacons too: the refinement would take them as residuals.
    if (z && !localization::is_plausible(config_.filter, *z)) {
      ++modes_.rejected_beacons[m];
      z.reset();
    }
    // A missing displacement is the filter's documented NaN input (filter.h: predict with d = 0
    // and missing_displacement_sigma_m), as in the rawlog replay.
    uav.filter->step(d_used.value_or(Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN())), z);
    const localization::Belief filtered = uav.filter->belief();
    localization::Belief belief = filtered;
    std::optional<CsiMeasurement> observed_csi;
    if (uav.refiner) {
      std::vector<CsiMeasurement> csi = measure_csi(m, q, iteration, uav.csi_rng);
      if (observer_ && !csi.empty()) observed_csi = csi.front();
      uav.refiner->add_epoch({filtered, d_used, z, std::move(csi)});
      const RefinementResult r = uav.refiner->refine();
      if (r.covariance_source == CovarianceSource::kDeadReckoning) ++modes_.refinement_covariance_fallbacks;
      belief = r.belief;
    }
    beliefs_[m] = belief;
    check_beliefs(m, epoch, uav, filtered, belief);
    if (fault_) return;  // a non-finite belief: not observed, no statistics, no placement
    if (observer_) observer_->on_epoch({epoch, m, q, d_used, z, observed_csi, filtered, belief});

    const Eigen::Vector3d e = belief.mean_m - q, e_f = filtered.mean_m - q;
    sums_.sq_m2 += e.squaredNorm();
    sums_.lateral_sq_m2 += e.tail<2>().squaredNorm();
    sums_.nees += nees(belief, q);
    sums_.filter_sq_m2 += e_f.squaredNorm();
    sums_.filter_lateral_sq_m2 += e_f.tail<2>().squaredNorm();
    sums_.filter_nees += nees(filtered, q);
    ++sums_.samples;
    if (z) {
      const Eigen::Vector3d e_b = localization::beacon_to_position(localization::to_vector(*z)) - q;
      sums_.beacon_sq_m2 += e_b.squaredNorm();
      sums_.beacon_lateral_sq_m2 += e_b.tail<2>().squaredNorm();
      ++sums_.beacons;
    }
  }
  ++modes_.num_epochs;
}

bool ClosedLoopPlanner::fault_active(UavFaultKind kind, int m, int iteration) const {
  for (const UavFault& f : config_.faults) {
    if (f.kind == kind && f.uav == m && f.active(iteration)) return true;
  }
  return false;
}

std::vector<CsiMeasurement> ClosedLoopPlanner::measure_csi(int m, const Eigen::Vector3d& q_m,
                                                           int iteration, std::mt19937_64& rng) {
  std::vector<CsiMeasurement> csi;
  if (!config_.refinement.use_csi) return csi;
  CsiMeasurement row = simulate_csi(model_, q_m, scenario_.noise_variance(), rng);
  if (fault_active(UavFaultKind::kNanCsi, m, iteration) && row.y.size() > 0)
    row.y(0) = std::complex<double>(std::numeric_limits<double>::quiet_NaN(), 0.0);
  if (row.y.allFinite()) {
    csi.push_back(std::move(row));
  } else {
    ++modes_.rejected_csi[m];
  }
  return csi;
}

void ClosedLoopPlanner::check_beliefs(int m, int epoch, const Uav& uav,
                                      const localization::Belief& filtered,
                                      const localization::Belief& belief) {
  if (fault_) return;
  const std::string filter = config_.filter_kind == localization::FilterKind::kEkf ? "EKF" : "PF";
  std::optional<std::string> problem = localization::health_problem(filtered);
  std::string what = filter + " belief ";
  if (!problem && uav.filter->counters().non_finite_state > 0) {
    problem = "state became non-finite (covariance reset)";
    what = filter + " ";
  }
  if (!problem && uav.refiner) {
    problem = localization::health_problem(belief);
    what = "refined belief ";
  }
  if (!problem) return;
  fault_ = placement::PlannerFault{placement::RunStatus::kNumericalFault, m,
                                   "UAV " + std::to_string(m) + ": " + what + *problem +
                                       " at epoch " + std::to_string(epoch)};
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
        fault_ = placement::PlannerFault{
            placement::RunStatus::kUavUnresponsive, static_cast<int>(m),
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
  if (fault_) return;  // a non-finite belief never reaches placement
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
      if (observer_) commanded = b_m * bf_probe_direction(probe);
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
      observer_->on_move({iteration, m, static_cast<UavMode>(modes[m]), false, commanded,
                          swarm.true_positions_m().col(m) - q_before});
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
      observer_->on_move({escape_iteration_, m, UavMode::kGd, true, best_offset,
                          swarm.true_positions_m().col(m) - q_before});
    }
    escape_rank_ = 0;
    return true;
  }
  return false;
}

ClosedLoopStats ClosedLoopPlanner::stats() const {
  ClosedLoopStats s = modes_;
  if (sums_.samples > 0) {
    const double n = static_cast<double>(sums_.samples);
    s.rmse_m = std::sqrt(sums_.sq_m2 / n);
    s.lateral_rmse_m = std::sqrt(sums_.lateral_sq_m2 / n);
    s.average_nees = sums_.nees / n;
    s.filter_rmse_m = std::sqrt(sums_.filter_sq_m2 / n);
    s.filter_lateral_rmse_m = std::sqrt(sums_.filter_lateral_sq_m2 / n);
    s.filter_average_nees = sums_.filter_nees / n;
  }
  s.num_beacons = static_cast<int>(sums_.beacons);
  if (sums_.beacons > 0) {
    s.beacon_only_rmse_m = std::sqrt(sums_.beacon_sq_m2 / static_cast<double>(sums_.beacons));
    s.beacon_only_lateral_rmse_m =
        std::sqrt(sums_.beacon_lateral_sq_m2 / static_cast<double>(sums_.beacons));
  }
  return s;
}

ClosedLoopRun run_closed_loop(const placement::PlacementSettings& settings,
                              const Eigen::Matrix3Xd& start_m, const ClosedLoopConfig& config,
                              std::uint64_t seed, ClosedLoopObserver* observer) {
  placement::ErrorModel errors = settings.errors;
  errors.sigma_loc_m = 0.0;  // the beliefs replace the Gaussian localization model
  const placement::ChannelModel model(settings.scenario);  // the Swarm keeps a pointer to it
  placement::Swarm swarm(model, start_m, errors,
                         derive_seed(seed, Stream::kSwarm, 0));
  ClosedLoopPlanner planner(settings.scenario, settings.gd, settings.bf, config, seed);
  planner.set_observer(observer);
  ClosedLoopRun out;
  out.run = placement::run_placement(planner, swarm, settings.run);
  out.stats = planner.stats();
  return out;
}

}  // namespace losmimo::fusion
