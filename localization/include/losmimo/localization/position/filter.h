#pragma once
// The common interface of the position filters (EKF and particle filter, both through MRPT).
//
// State q_k = UAV position at epoch k in the BS array frame [m] (position only: the UAV's
// velocity is not estimated; dead reckoning supplies the motion between epochs).
// Motion:  q_k = q_{k-1} + d_k - n_k,  d_k the measured displacement (dead reckoning),
//          n_k ~ N(0, sigma_d(|d_k|)^2 I),  sigma_d(s) = dr_sigma_floor_m + dr_sigma_fraction * s.
//          The actuation error is inside the true displacement that dead reckoning measures,
//          so it needs no separate term here.
// Beacon:  z_k = h(q_k) + v_k, v_k ~ N(0, R) (beacon_model.h).
//
// One call to step() is one epoch: predict with d_k, then fuse the beacon if there is one and
// it passes the checks. Robustness, on by default:
//  - non-finite displacement: the epoch predicts with d = 0 and sigma missing_displacement_sigma_m;
//  - non-finite beacon, or beacon with rho < kMinBeaconRho_m at the prediction: not fused;
//  - physically implausible beacon: range_m > max_beacon_range_m, or an elevation outside
//    [-pi/2, pi/2] once wrapped to (-pi, pi] (any finite azimuth is a direction after
//    wrapping): never fused, never used for a reset, and not a gate rejection (it neither
//    counts towards reset_after_rejections nor clears that count, exactly as if the epoch had
//    no beacon); counted in FilterCounters::rejected_out_of_range_beacon;
//  - Mahalanobis gate: fuse only if y^T S^-1 y <= gate_chi2 (y innovation, S = H P H^T + R);
//    after reset_after_rejections gated beacons in a row the filter re-initialises from the
//    next beacon fix (the belief had lost track, and the gate would reject forever);
//  - noise floors on every sigma; covariance symmetrised with eigenvalues >= min_variance_m2;
//  - degraded when epochs_since_beacon >= degraded_after_epochs, or when the largest 1-sigma
//    axis of the covariance exceeds degraded_sigma_m;
//  - counters of everything rejected (FilterCounters);
//  - numerical health: a covariance that becomes non-finite (e.g. a beacon fix at an absurd
//    range overflows r^2 sigma_angle^2) is replaced by missing_displacement_sigma_m^2 I and
//    counted in FilterCounters::non_finite_state; health_problem() reports it, and a
//    non-finite or inconsistent belief, so that the caller can stop (the closed loop does).

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "losmimo/common/range.h"
#include "losmimo/localization/position/measurements.h"

namespace losmimo::localization {

enum class FilterKind { kEkf, kParticle };
enum class ResamplingMethod { kMultinomial, kResidual, kStratified, kSystematic };

std::string to_string(FilterKind kind);
FilterKind filter_kind_from_string(const std::string& text);  // "ekf" or "pf"
std::string to_string(ResamplingMethod method);
// "multinomial", "residual", "stratified" or "systematic".
ResamplingMethod resampling_method_from_string(const std::string& text);

// What the filter assumes about its sensors (the truth lives in SimulatorConfig).
struct NoiseModel {
  double sigma_range_m = 0.1;       // beacon range 1-sigma
  double sigma_angle_rad = 1e-4;    // beacon azimuth and elevation 1-sigma
  double dr_sigma_floor_m = 0.01;   // dead-reckoning 1-sigma per axis, per epoch, at rest
  double dr_sigma_fraction = 0.02;  // ... plus this fraction of the distance moved
};

struct FilterConfig {
  NoiseModel noise;

  // Gate on the squared Mahalanobis distance of the innovation; 16.27 is the 3-dof chi-square
  // quantile at p = 0.999 (a clean beacon is rejected once in a thousand).
  bool gate_enabled = true;
  double gate_chi2 = 16.27;
  int reset_after_rejections = 10;  // 0: never re-initialise from a beacon fix

  // Physical plausibility: the largest beacon range a real ranging sensor reports [m], finite
  // and > 0. The default, 1e5 m = 100 km, is 100 times the paper's BS-to-swarm range (~1000 m)
  // and beyond the radio horizon of a UAV at a few hundred metres (tens of km), so no genuine
  // beacon of the LoS link comes from farther. It also keeps a beacon fix finite: its lateral
  // 1-sigma is r * sigma_angle_rad, and at r = 1e300 m the covariance overflows. The scenario
  // accepts lengths up to 1e7 m (placement/scenario.cpp): a swarm placed farther than 1e5 m
  // needs a larger value here, or every beacon is rejected (and counted).
  double max_beacon_range_m = 1e5;

  int degraded_after_epochs = 10;
  double degraded_sigma_m = 1.0;

  // Noise floors: the filter never assumes a sensor better than this.
  double min_sigma_range_m = 1e-3;
  double min_sigma_angle_rad = 1e-6;
  double min_sigma_displacement_m = 1e-4;
  double min_variance_m2 = 1e-10;  // eigenvalue floor of the covariance
  double missing_displacement_sigma_m = 1.0;

  // Particle filter only.
  int num_particles = 1000;
  ResamplingMethod resampling = ResamplingMethod::kSystematic;
  double ess_threshold = 0.5;  // resample when ESS / N < this, in (0, 1]
  // Kernel bandwidth h of the jitter after each resampling (particle_filter.h), in [0, 1).
  double regularization_bandwidth = 0.2;
};

// The values each field accepts (validate() and the keys that set them).
namespace filter_range {
inline constexpr common::Range sigma = common::Range::at_least(0.0);  // each of noise's four
inline constexpr common::Range gate_chi2 = common::Range::above(0.0);
inline constexpr common::Range reset_after_rejections = common::Range::at_least(0);
inline constexpr common::Range max_beacon_range_m = common::Range::above(0.0);
inline constexpr common::Range degraded_after_epochs = common::Range::closed(1, 1'000'000);
inline constexpr common::Range positive = common::Range::above(0.0);  // the sigmas and floors below it
inline constexpr common::Range num_particles = common::Range::closed(1, 1'000'000);
inline constexpr common::Range ess_threshold = common::Range::above_up_to(0.0, 1.0);
inline constexpr common::Range regularization_bandwidth = {0.0, 1.0, false, true};  // [0, 1)
}  // namespace filter_range

// Throws common::FieldError naming the first bad field and its value.
void validate(const FilterConfig& config);
// Throws std::invalid_argument if the belief is non-finite or its covariance not SPD.
void validate(const Belief& belief);

// The first numerical problem of a belief, or nullopt when it is healthy: a non-finite mean
// ("mean_m(1) = nan") or covariance entry ("cov_m2(0, 2) = inf"), a negative variance
// ("cov_m2(2, 2) = -0.5 < 0") or an asymmetric covariance. Cheap (no factorisation): for a
// check after every epoch; validate() is the strict test (SPD) for inputs.
std::optional<std::string> health_problem(const Belief& belief);

struct FilterCounters {
  std::int64_t epochs = 0;
  std::int64_t beacons_received = 0;  // step() calls with a beacon
  std::int64_t beacons_fused = 0;
  std::int64_t rejected_non_finite_displacement = 0;
  std::int64_t rejected_non_finite_beacon = 0;  // non-finite, or range_m <= 0
  // Finite but physically implausible: range_m > max_beacon_range_m, or elevation outside
  // [-pi/2, pi/2] after wrapping. Not gate rejections: they never lead to a reset.
  std::int64_t rejected_out_of_range_beacon = 0;
  std::int64_t rejected_geometry = 0;  // prediction too close to the array's z axis
  std::int64_t rejected_gate = 0;
  std::int64_t resets = 0;              // re-initialisations from a beacon fix
  std::int64_t covariance_repairs = 0;  // eigenvalues raised to min_variance_m2
  std::int64_t resamplings = 0;         // particle filter only
  // Epochs in which the state became non-finite (the covariance was reset, see above).
  std::int64_t non_finite_state = 0;

  // Ranges to mapped beacons (the pose filters, pose/filter.h): every reading of every scan is
  // counted once in ranges_received, then either fused (ranges_fused, which includes the
  // readings of a reset's fix) or rejected for exactly one reason (range_model.h's screen,
  // then the filter's geometry and gate checks).
  std::int64_t ranges_received = 0;
  std::int64_t ranges_fused = 0;
  std::int64_t rejected_non_finite_range = 0;       // non-finite or <= 0 (or its scan's stdError)
  std::int64_t rejected_unknown_beacon = 0;         // ID not in the beacon map
  std::int64_t rejected_outside_sensor_limits = 0;  // outside [min, max]SensorDistance
  std::int64_t rejected_implausible_range = 0;      // above max_beacon_range_m
  std::int64_t rejected_range_geometry = 0;         // predicted sensor-beacon distance ~ 0
  std::int64_t rejected_range_gate = 0;

  std::int64_t rejected_ranges() const {
    return rejected_non_finite_range + rejected_unknown_beacon + rejected_outside_sensor_limits +
           rejected_implausible_range + rejected_range_geometry + rejected_range_gate;
  }
  std::int64_t rejected_total() const {
    return rejected_non_finite_displacement + rejected_non_finite_beacon +
           rejected_out_of_range_beacon + rejected_geometry + rejected_gate + rejected_ranges();
  }

  // Field by field: the counts of several filter runs (e.g. a start fix and the filter after it).
  FilterCounters& operator+=(const FilterCounters& other);
};

class PositionFilter {
 public:
  virtual ~PositionFilter() = default;

  // One epoch: prediction with the measured displacement, then the beacon if any.
  virtual void step(const Eigen::Vector3d& measured_displacement_m,
                    const std::optional<BeaconMeasurement>& beacon) = 0;
  virtual Belief belief() const = 0;
  virtual const FilterCounters& counters() const = 0;
  virtual FilterKind kind() const = 0;
};

// The filter's health after a step: health_problem(filter.belief()), or, if the state ever
// became non-finite (FilterCounters::non_finite_state), "state became non-finite in N
// epoch(s), covariance reset". nullopt when healthy.
std::optional<std::string> health_problem(const PositionFilter& filter);

// A filter starting from `initial` (validated). `seed` drives the filter's own random generator
// (the particle filter's; the EKF draws no random numbers): equal seeds, equal results, in any
// thread.
std::unique_ptr<PositionFilter> make_filter(FilterKind kind, const FilterConfig& config,
                                            const Belief& initial, std::uint64_t seed);

}  // namespace losmimo::localization
