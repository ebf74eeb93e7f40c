#pragma once
// What both filter families configure (position/filter.h, pose/filter.h): the filter kind, the
// resampling method, the sensor noise the filter assumes, the gate, reset, plausibility,
// degradation and floor settings, and the particle filters' options. A pose filter takes the
// shared part as PoseFilterConfig::filter (which of its fields a pose filter reads: pose/filter.h).

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

#include "losmimo/placement/common/range.h"

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

// The factories' rule (make_filter, make_pose_filter): the EKF takes the filter's arguments, the
// particle filter the same and the seed of its own generator (the EKF draws no random numbers).
template <class Base, class Ekf, class Particle, class... Args>
std::unique_ptr<Base> make_filter_of_kind(FilterKind kind, std::uint64_t seed, const Args&... args) {
  switch (kind) {
    case FilterKind::kEkf:
      return std::make_unique<Ekf>(args...);
    case FilterKind::kParticle:
      return std::make_unique<Particle>(args..., seed);
  }
  throw std::invalid_argument("localization: unknown filter kind");
}

}  // namespace losmimo::localization
