#include "losmimo/fusion/closed_loop_settings.h"
#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/text.h"

#include <limits>
#include <sstream>
#include <vector>

namespace losmimo::fusion {

namespace {

using common::Range;
constexpr const char* kLoop = "closed_loop";
constexpr common::Range kOutageEpoch = localization::simulator_range::outage_epoch;
constexpr long long lo(const common::Range& r) { return static_cast<long long>(r.lo); }
constexpr long long hi(const common::Range& r) { return static_cast<long long>(r.hi); }

// "uav:first_epoch:num_epochs, ..."; errors name the entry. UAV indices are checked against the
// swarm by load_closed_loop_config.
std::vector<UavBeaconOutage> parse_outages(const std::string& text, const std::string& where) {
  std::vector<UavBeaconOutage> out;
  std::stringstream list(text);
  std::string item;
  while (std::getline(list, item, ',')) {
    item = common::trim(item);
    if (item.empty()) continue;
    std::stringstream parts(item);
    std::string a, b, c, extra;
    if (!std::getline(parts, a, ':') || !std::getline(parts, b, ':') || !std::getline(parts, c, ':') ||
        std::getline(parts, extra, ':')) {
      throw common::InputError(where + ": outage '" + item + "': expected uav:first_epoch:num_epochs");
    }
    const std::string w = where + ": outage '" + item + "'";
    UavBeaconOutage o;
    o.uav = static_cast<int>(
        common::parse_integer(common::trim(a), w + " uav", lo(closed_loop_range::uav), hi(closed_loop_range::uav)));
    o.window.first_epoch = static_cast<int>(
        common::parse_integer(common::trim(b), w + " first_epoch", lo(kOutageEpoch), hi(kOutageEpoch)));
    o.window.num_epochs =
        static_cast<int>(common::parse_integer(common::trim(c), w + " num_epochs", lo(kOutageEpoch), hi(kOutageEpoch)));
    out.push_back(o);
  }
  return out;
}

std::string outages_text(const std::vector<UavBeaconOutage>& outages) {
  std::ostringstream o;
  for (std::size_t i = 0; i < outages.size(); ++i) {
    const UavBeaconOutage& u = outages[i];
    o << (i ? ", " : "") << u.uav << ":" << u.window.first_epoch << ":" << u.window.num_epochs;
  }
  return o.str();
}

// "x, y, z" [m], each in simulator_range::position_error; errors name the item.
Eigen::Vector3d parse_position_error(const std::string& text, const std::string& where) {
  const std::vector<std::string> items = common::split_list(text);
  if (items.size() != 3) {
    throw common::InputError(where + ": '" + text + "': expected three numbers x, y, z [m], got " +
                             std::to_string(items.size()));
  }
  Eigen::Vector3d p;
  for (int a = 0; a < 3; ++a) {
    p(a) = common::parse_double(items[static_cast<std::size_t>(a)], where);
    common::require_in(localization::simulator_range::position_error, p(a), items[static_cast<std::size_t>(a)], where);
  }
  return p;
}

std::string position_text(const Eigen::Vector3d& p) {
  return common::format_exact(p.x()) + ", " + common::format_exact(p.y()) + ", " + common::format_exact(p.z());
}

// "kind:uav:from_iteration[:num_iterations], ..."; errors name the entry.
std::vector<UavFault> parse_faults(const std::string& text, const std::string& where) {
  std::vector<UavFault> out;
  std::stringstream list(text);
  std::string item;
  while (std::getline(list, item, ',')) {
    item = common::trim(item);
    if (item.empty()) continue;
    std::vector<std::string> parts;
    std::stringstream fields(item);
    std::string part;
    while (std::getline(fields, part, ':')) parts.push_back(common::trim(part));
    if (parts.size() < 3 || parts.size() > 4) {
      throw common::InputError(where + ": fault '" + item + "': expected kind:uav:from_iteration[:num_iterations]");
    }
    const std::string w = where + ": fault '" + item + "'";
    UavFault f;
    try {
      f.kind = uav_fault_kind_from_string(parts[0]);
    } catch (const std::invalid_argument& e) {
      throw common::InputError(w + ": " + e.what());
    }
    f.uav = static_cast<int>(
        common::parse_integer(parts[1], w + " uav", lo(closed_loop_range::uav), hi(closed_loop_range::uav)));
    f.from_iteration = static_cast<int>(common::parse_integer(parts[2], w + " from_iteration",
                                                              lo(closed_loop_range::fault_from_iteration),
                                                              hi(closed_loop_range::fault_from_iteration)));
    if (parts.size() == 4) {
      f.num_iterations = static_cast<int>(common::parse_integer(parts[3], w + " num_iterations",
                                                                lo(closed_loop_range::fault_num_iterations),
                                                                hi(closed_loop_range::fault_num_iterations)));
    }
    out.push_back(f);
  }
  return out;
}

std::string faults_text(const std::vector<UavFault>& faults) {
  std::ostringstream o;
  for (std::size_t i = 0; i < faults.size(); ++i) {
    const UavFault& f = faults[i];
    o << (i ? ", " : "") << to_string(f.kind) << ":" << f.uav << ":" << f.from_iteration << ":" << f.num_iterations;
  }
  return o.str();
}

// What the filter and the refinement assume of the beacon (the truth's unless given).
void set_filter_sigma_range(ClosedLoopConfig& c, double v) {
  c.filter.noise.sigma_range_m = c.refinement.beacon_sigma_range_m = v;
}
void set_filter_sigma_angle(ClosedLoopConfig& c, double v) {
  c.filter.noise.sigma_angle_rad = c.refinement.beacon_sigma_angle_rad = v;
}

std::vector<common::Key<ClosedLoopConfig>> closed_loop_key_list() {
  using K = common::Key<ClosedLoopConfig>;
  return {
      K::text(
          kLoop, "filter",
          [](ClosedLoopConfig& c, const std::string& text, const std::string&) {
            c.filter_kind = localization::filter_kind_from_string(text);
          },
          [](const ClosedLoopConfig& c) { return localization::to_string(c.filter_kind); }, "ekf | pf",
          "the UAVs' position filter", "pf")
          .sets({"filter_kind"}),
      K::integer(
          kLoop, "num_particles", [](auto& c) -> auto& { return c.filter.num_particles; },
          localization::filter_range::num_particles, "particle filter size", "200")
          .sets({"filter.num_particles"}),
      K::boolean(kLoop, "refine", &ClosedLoopConfig::refine, "Ceres sliding-window refinement (refinement.h)", "true"),
      K::boolean(
          kLoop, "use_csi", [](auto& c) -> auto& { return c.refinement.use_csi; }, "CSI rows in the refinement",
          "false")
          .sets({"refinement.use_csi"}),
      K::integer(
          kLoop, "window_epochs", [](auto& c) -> auto& { return c.refinement.window_epochs; },
          refinement_range::window_epochs, "refinement window W [epochs]", "8")
          .sets({"refinement.window_epochs"}),
      K::boolean(kLoop, "fallback", &ClosedLoopConfig::fallback_to_bf, "BF for a UAV whose belief is degraded", "false")
          .sets({"fallback_to_bf"}),
      K::text(
          kLoop, "gd_mode",
          [](ClosedLoopConfig& c, const std::string& text, const std::string&) {
            c.gd_mode = gd_belief_mode_from_string(text);
          },
          [](const ClosedLoopConfig& c) { return to_string(c.gd_mode); }, "mean | sigma_points",
          "where GD evaluates its move from the belief", "sigma_points"),
      K::real(
          kLoop, "beacon_sigma_range_m", [](auto& c) -> auto& { return c.simulator.sigma_range_m; },
          localization::simulator_range::sigma, "true beacon range 1-sigma [m]", "0.25")
          .sets({"simulator.sigma_range_m"}),
      K::real(
          kLoop, "beacon_sigma_angle_rad", [](auto& c) -> auto& { return c.simulator.sigma_angle_rad; },
          localization::simulator_range::sigma, "true beacon azimuth and elevation 1-sigma [rad]", "0.000244140625")
          .sets({"simulator.sigma_angle_rad"}),
      K::integer(
          kLoop, "beacon_period_epochs", [](auto& c) -> auto& { return c.simulator.beacon_period_epochs; },
          localization::simulator_range::beacon_period_epochs, "a beacon every N epochs", "2")
          .sets({"simulator.beacon_period_epochs"}),
      K::real(
          kLoop, "outlier_fraction", [](auto& c) -> auto& { return c.simulator.outlier_fraction; },
          localization::simulator_range::outlier_fraction, "fraction of beacons with gross errors, in [0, 1]", "0.125")
          .sets({"simulator.outlier_fraction"}),
      // Common-mode errors (localization/position/simulator.h): only written when set, so that
      // the CONFIG of a mission without them stays as it was.
      K::real(
          kLoop, "bs_azimuth_bias_rad", [](auto& c) -> auto& { return c.simulator.bs_azimuth_bias_rad; },
          localization::simulator_range::angle_bias,
          "BS array azimuth misalignment [rad]: every UAV's beacon azimuth reads this much more (the filters do "
          "not know it)",
          "0.0009765625")
          .sets({"simulator.bs_azimuth_bias_rad"})
          .unless_default(),
      K::real(
          kLoop, "bs_elevation_bias_rad", [](auto& c) -> auto& { return c.simulator.bs_elevation_bias_rad; },
          localization::simulator_range::angle_bias, "BS array elevation misalignment [rad], as above",
          "-0.00048828125")
          .sets({"simulator.bs_elevation_bias_rad"})
          .unless_default(),
      K::real(
          kLoop, "beacon_range_bias_m", [](auto& c) -> auto& { return c.simulator.beacon_range_bias_m; },
          localization::simulator_range::position_error, "a range bias shared by every UAV's beacon [m]", "0.5")
          .sets({"simulator.beacon_range_bias_m"})
          .unless_default(),
      K::text(
          kLoop, "bs_position_error_m",
          [](ClosedLoopConfig& c, const std::string& text, const std::string& where) {
            c.simulator.bs_position_error_m = parse_position_error(text, where);
          },
          [](const ClosedLoopConfig& c) { return position_text(c.simulator.bs_position_error_m); },
          "x, y, z: three numbers in [-1000, 1000]",
          "where the BS stands relative to where the filters assume it, BS frame [m]", "0, 0.5, 0")
          .sets({"simulator.bs_position_error_m"})
          .unless_default(),
      K::real(
          kLoop, "dr_sigma_floor_m", [](const ClosedLoopConfig& c) { return c.simulator.dr_sigma_floor_m; },
          [](ClosedLoopConfig& c, double v) {
            c.simulator.dr_sigma_floor_m = c.filter.noise.dr_sigma_floor_m = c.refinement.dr_sigma_floor_m = v;
          },
          // the strictest of the three fields' ranges
          refinement_range::positive, "dead-reckoning 1-sigma per axis at rest [m] (true and assumed)", "0.015625")
          .sets({"simulator.dr_sigma_floor_m", "filter.noise.dr_sigma_floor_m", "refinement.dr_sigma_floor_m"}),
      K::real(
          kLoop, "dr_sigma_fraction", [](const ClosedLoopConfig& c) { return c.simulator.dr_sigma_fraction; },
          [](ClosedLoopConfig& c, double v) {
            c.simulator.dr_sigma_fraction = c.filter.noise.dr_sigma_fraction = c.refinement.dr_sigma_fraction = v;
          },
          refinement_range::dr_sigma_fraction, "... plus this fraction of the distance moved (true and assumed)",
          "0.0625")
          .sets({"simulator.dr_sigma_fraction", "filter.noise.dr_sigma_fraction", "refinement.dr_sigma_fraction"}),
      K::real(
          kLoop, "filter_sigma_range_m", [](const ClosedLoopConfig& c) { return c.filter.noise.sigma_range_m; },
          // the stricter of the two fields' ranges
          set_filter_sigma_range, refinement_range::positive,
          "beacon range 1-sigma the filter assumes [m] (default: the true one)", "0.375")
          .sets({"filter.noise.sigma_range_m", "refinement.beacon_sigma_range_m"})
          .when_absent([](ClosedLoopConfig& c) { set_filter_sigma_range(c, c.simulator.sigma_range_m); }),
      K::real(
          kLoop, "filter_sigma_angle_rad", [](const ClosedLoopConfig& c) { return c.filter.noise.sigma_angle_rad; },
          set_filter_sigma_angle, refinement_range::positive,
          "beacon angle 1-sigma the filter assumes [rad] (default: the true one)", "0.00048828125")
          .sets({"filter.noise.sigma_angle_rad", "refinement.beacon_sigma_angle_rad"})
          .when_absent([](ClosedLoopConfig& c) { set_filter_sigma_angle(c, c.simulator.sigma_angle_rad); }),
      K::integer(
          kLoop, "degraded_after_epochs", [](auto& c) -> auto& { return c.filter.degraded_after_epochs; },
          localization::filter_range::degraded_after_epochs, "a belief is degraded after N epochs without beacon", "5")
          .sets({"filter.degraded_after_epochs"}),
      K::text(
          kLoop, "outages",
          [](ClosedLoopConfig& c, const std::string& text, const std::string& where) {
            c.outages = parse_outages(text, where);
          },
          [](const ClosedLoopConfig& c) { return outages_text(c.outages); }, "uav:first_epoch:num_epochs, ...",
          "per-UAV beacon outages (none)", "2:0:10"),
      // Only when set: the CONFIG of a mission without them stays as it was.
      K::text(
          kLoop, "faults",
          [](ClosedLoopConfig& c, const std::string& text, const std::string& where) {
            c.faults = parse_faults(text, where);
          },
          [](const ClosedLoopConfig& c) { return faults_text(c.faults); },
          "kind:uav:from_iteration[:num_iterations], ...; kind unresponsive | nan_beacon | nan_displacement | "
          "nan_csi; num_iterations 0 = to the end",
          "injected faults (closed_loop.h UavFault; none)", "unresponsive:1:5:0")
          .unless_default(),
      K::real(
          kLoop, "filter_max_beacon_range_m", [](auto& c) -> auto& { return c.filter.max_beacon_range_m; },
          localization::filter_range::max_beacon_range_m,
          "the largest plausible beacon range [m] (localization/filter.h)", "2500")
          .sets({"filter.max_beacon_range_m"})
          .unless_default(),
      K::integer(kLoop, "unresponsive_after_iterations", &ClosedLoopConfig::unresponsive_after_iterations,
                 closed_loop_range::unresponsive_after_iterations,
                 "the run ends after a UAV is silent (no measurement, no motion) this many iterations", "5")
          .written_if([](const ClosedLoopConfig& c) {
            const int by_default = ClosedLoopConfig{}.unresponsive_after_iterations;
            return !c.faults.empty() || c.unresponsive_after_iterations != by_default;
          }),
  };
}

}  // namespace

const common::KeyTable<ClosedLoopConfig>& closed_loop_keys() {
  static const common::KeyTable<ClosedLoopConfig> table(closed_loop_key_list(), &common::format_exact);
  return table;
}

ClosedLoopConfig load_closed_loop_config(const common::IniConfig& ini, const placement::PlacementSettings& placement) {
  localization::SimulatorConfig truth;
  truth.sigma_act_m = placement.errors.sigma_act_m;
  ClosedLoopConfig c = matched_closed_loop_config(truth, placement.scenario);
  const common::KeyTable<ClosedLoopConfig>& keys = closed_loop_keys();
  keys.load(ini, c);
  keys.check(ini, "", [&] {
    for (const UavFault& f : c.faults) {
      if (f.kind == UavFaultKind::kNanCsi && !(c.refine && c.refinement.use_csi)) {
        throw common::FieldError("faults", "nan_csi needs refine = true and use_csi = true");
      }
    }
    validate(c);
    require_uavs_in_swarm(c, placement.scenario.num_uavs);
  });
  return c;
}

std::string closed_loop_to_ini(const ClosedLoopConfig& config) { return closed_loop_keys().to_ini(config); }

}  // namespace losmimo::fusion
