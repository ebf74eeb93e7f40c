// The closed loop's configuration: the names of its choices, its validation and the matched
// filter config (closed_loop.h).
#include "losmimo/fusion/closed_loop.h"

#include <stdexcept>
#include <string>

#include "losmimo/placement/common/field_error.h"
#include "losmimo/placement/common/range.h"

namespace losmimo::fusion {

std::string to_string(GdBeliefMode mode) { return mode == GdBeliefMode::kMean ? "mean" : "sigma_points"; }

GdBeliefMode gd_belief_mode_from_string(const std::string& text) {
  if (text == "mean") return GdBeliefMode::kMean;
  if (text == "sigma_points") return GdBeliefMode::kSigmaPoints;
  throw std::invalid_argument("closed_loop.gd_mode = '" + text + "': must be mean or sigma_points");
}

std::string to_string(UavFaultKind kind) {
  switch (kind) {
    case UavFaultKind::kUnresponsive:
      return "unresponsive";
    case UavFaultKind::kNanBeacon:
      return "nan_beacon";
    case UavFaultKind::kNanDisplacement:
      return "nan_displacement";
    case UavFaultKind::kNanCsi:
      return "nan_csi";
  }
  return "unknown";
}

UavFaultKind uav_fault_kind_from_string(const std::string& text) {
  for (const UavFaultKind kind :
       {UavFaultKind::kUnresponsive, UavFaultKind::kNanBeacon, UavFaultKind::kNanDisplacement, UavFaultKind::kNanCsi}) {
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
  namespace r = closed_loop_range;
  const auto require = [](const common::Range& range, double value, const std::string& field) {
    common::require_field_in(range, value, "closed_loop", field);
  };
  require(r::unresponsive_after_iterations, config.unresponsive_after_iterations, "unresponsive_after_iterations");
  for (std::size_t i = 0; i < config.faults.size(); ++i) {
    const UavFault& f = config.faults[i];
    const std::string field = "faults[" + std::to_string(i) + "]";
    require(r::uav, f.uav, field + ".uav");
    require(r::fault_from_iteration, f.from_iteration, field + ".from_iteration");
    require(r::fault_num_iterations, f.num_iterations, field + ".num_iterations");
    if (f.kind == UavFaultKind::kNanCsi && !(config.refine && config.refinement.use_csi)) {
      throw common::FieldError(field, "closed_loop." + field +
                                          " = nan_csi: needs refine = true and use_csi = true (no CSI "
                                          "is measured otherwise)");
    }
  }
  for (std::size_t i = 0; i < config.outages.size(); ++i) {
    const UavBeaconOutage& o = config.outages[i];
    const std::string field = "outages[" + std::to_string(i) + "]";
    require(r::uav, o.uav, field + ".uav");
    require(localization::simulator_range::outage_epoch, o.window.first_epoch, field + ".first_epoch");
    require(localization::simulator_range::outage_epoch, o.window.num_epochs, field + ".num_epochs");
  }
}

void require_uavs_in_swarm(const ClosedLoopConfig& config, int num_uavs) {
  const auto require_uav = [num_uavs](const std::string& field, int uav) {
    if (uav >= num_uavs) {
      throw common::FieldError(field, "closed_loop." + field + " = " + std::to_string(uav) +
                                          ": must be < the number of UAVs (" + std::to_string(num_uavs) + ")");
    }
  };
  for (std::size_t i = 0; i < config.outages.size(); ++i) {
    require_uav("outages[" + std::to_string(i) + "].uav", config.outages[i].uav);
  }
  for (std::size_t i = 0; i < config.faults.size(); ++i) {
    require_uav("faults[" + std::to_string(i) + "].uav", config.faults[i].uav);
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

}  // namespace losmimo::fusion
