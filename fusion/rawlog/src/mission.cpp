#include "losmimo/common/ini_config.h"
#include "losmimo/rawlog/mission.h"

#include <iomanip>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>

#include "losmimo/common/input_error.h"
#include "losmimo/placement/scenario.h"

namespace losmimo::rawlog {

namespace {

using common::InputError;
constexpr const char* kLoop = "closed_loop";
constexpr const char* kMission = "mission";

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

// "uav:first:count, ..." -> outages; errors name the entry.
std::vector<fusion::UavBeaconOutage> parse_outages(const std::string& text, const std::string& where,
                                           int num_uavs) {
  std::vector<fusion::UavBeaconOutage> out;
  std::stringstream list(text);
  std::string item;
  while (std::getline(list, item, ',')) {
    item = trim(item);
    if (item.empty()) continue;
    std::stringstream parts(item);
    std::string a, b, c, extra;
    if (!std::getline(parts, a, ':') || !std::getline(parts, b, ':') ||
        !std::getline(parts, c, ':') || std::getline(parts, extra, ':')) {
      throw common::InputError(where + ": outage '" + item + "': expected uav:first_epoch:num_epochs");
    }
    const std::string w = where + ": outage '" + item + "'";
    fusion::UavBeaconOutage o;
    o.uav = static_cast<int>(common::parse_integer(trim(a), w + " uav", 0, num_uavs - 1));
    o.window.first_epoch =
        static_cast<int>(common::parse_integer(trim(b), w + " first_epoch", 0, 1'000'000'000));
    o.window.num_epochs =
        static_cast<int>(common::parse_integer(trim(c), w + " num_epochs", 0, 1'000'000'000));
    out.push_back(o);
  }
  return out;
}

// "kind:uav:from_iteration[:num_iterations], ..." -> faults; errors name the entry.
std::vector<fusion::UavFault> parse_faults(const std::string& text, const std::string& where, int num_uavs) {
  std::vector<fusion::UavFault> out;
  std::stringstream list(text);
  std::string item;
  while (std::getline(list, item, ',')) {
    item = trim(item);
    if (item.empty()) continue;
    std::vector<std::string> parts;
    std::stringstream fields(item);
    std::string part;
    while (std::getline(fields, part, ':')) parts.push_back(trim(part));
    if (parts.size() < 3 || parts.size() > 4) {
      throw common::InputError(where + ": fault '" + item +
                       "': expected kind:uav:from_iteration[:num_iterations]");
    }
    const std::string w = where + ": fault '" + item + "'";
    fusion::UavFault f;
    try {
      f.kind = fusion::uav_fault_kind_from_string(parts[0]);
    } catch (const std::invalid_argument& e) {
      throw common::InputError(w + ": " + e.what());
    }
    f.uav = static_cast<int>(common::parse_integer(parts[1], w + " uav", 0, num_uavs - 1));
    f.from_iteration =
        static_cast<int>(common::parse_integer(parts[2], w + " from_iteration", 1, 10'000'000));
    if (parts.size() == 4) {
      f.num_iterations =
          static_cast<int>(common::parse_integer(parts[3], w + " num_iterations", 0, 10'000'000));
    }
    out.push_back(f);
  }
  return out;
}

template <typename Fn>
void check(const common::IniConfig& ini, const std::string& key, Fn&& fn) {
  try {
    fn();
  } catch (const std::invalid_argument& e) {
    const std::string at = ini.has(kLoop, key) ? ini.where(kLoop, key) : std::string("config");
    throw common::InputError(at + ": " + e.what());
  }
}

}  // namespace

std::map<std::string, std::set<std::string>> mission_config_keys(
    std::map<std::string, std::set<std::string>> also_known) {
  auto keys = std::move(also_known);
  for (auto& [section, names] : placement::placement_config_keys()) keys[section].insert(names.begin(), names.end());
  keys[kLoop] = {"filter",
                 "num_particles",
                 "refine",
                 "use_csi",
                 "window_epochs",
                 "fallback",
                 "gd_mode",
                 "beacon_sigma_range_m",
                 "beacon_sigma_angle_rad",
                 "beacon_period_epochs",
                 "outlier_fraction",
                 "dr_sigma_floor_m",
                 "dr_sigma_fraction",
                 "filter_sigma_range_m",
                 "filter_sigma_angle_rad",
                 "filter_max_beacon_range_m",
                 "degraded_after_epochs",
                 "outages",
                 "faults",
                 "unresponsive_after_iterations"};
  keys[kMission] = {"seed", "start_seed", "epoch_period_s"};
  return keys;
}

MissionConfig load_mission_config(const common::IniConfig& ini,
                                  const std::map<std::string, std::set<std::string>>& also_known) {
  ini.require_known(mission_config_keys(also_known));
  MissionConfig c;
  c.ini = ini;
  c.placement = placement::load_placement_settings(ini);
  const placement::Scenario& sc = c.placement.scenario;

  localization::SimulatorConfig sim;
  sim.sigma_range_m = ini.get_double(kLoop, "beacon_sigma_range_m", sim.sigma_range_m);
  sim.sigma_angle_rad = ini.get_double(kLoop, "beacon_sigma_angle_rad", sim.sigma_angle_rad);
  sim.beacon_period_epochs = static_cast<int>(
      ini.get_integer(kLoop, "beacon_period_epochs", sim.beacon_period_epochs, 1, 1'000'000));
  sim.outlier_fraction = ini.get_double(kLoop, "outlier_fraction", sim.outlier_fraction);
  sim.dr_sigma_floor_m = ini.get_double(kLoop, "dr_sigma_floor_m", sim.dr_sigma_floor_m);
  sim.dr_sigma_fraction = ini.get_double(kLoop, "dr_sigma_fraction", sim.dr_sigma_fraction);
  sim.sigma_act_m = c.placement.errors.sigma_act_m;
  const auto check_sim = [&](const std::string& key) {
    check(ini, key, [&] { localization::validate(sim); });
  };
  check_sim("beacon_sigma_range_m");

  fusion::ClosedLoopConfig& cl = c.closed_loop;
  // The refinement's own checks (e.g. dr_sigma_floor_m > 0) throw std::invalid_argument: name
  // the key (found by fuzz_rawlog: a CONFIG with dr_sigma_floor_m = 0 escaped as a non-common::InputError).
  check(ini, "dr_sigma_floor_m", [&] { cl = fusion::matched_closed_loop_config(sim, sc); });
  const std::string filter = ini.get_string(kLoop, "filter", "ekf");
  check(ini, "filter", [&] { cl.filter_kind = localization::filter_kind_from_string(filter); });
  cl.filter.num_particles = static_cast<int>(
      ini.get_integer(kLoop, "num_particles", cl.filter.num_particles, 1, 1'000'000));
  cl.filter.noise.sigma_range_m = ini.get_double(kLoop, "filter_sigma_range_m", sim.sigma_range_m);
  cl.filter.noise.sigma_angle_rad =
      ini.get_double(kLoop, "filter_sigma_angle_rad", sim.sigma_angle_rad);
  cl.filter.degraded_after_epochs = static_cast<int>(
      ini.get_integer(kLoop, "degraded_after_epochs", cl.filter.degraded_after_epochs, 1, 1'000'000));
  cl.filter.max_beacon_range_m =
      ini.get_double(kLoop, "filter_max_beacon_range_m", cl.filter.max_beacon_range_m);
  // Checked on its own first, so that a bad limit is not reported as filter_sigma_range_m's.
  check(ini, "filter_max_beacon_range_m", [&] {
    localization::FilterConfig limit_only;
    limit_only.max_beacon_range_m = cl.filter.max_beacon_range_m;
    localization::validate(limit_only);
  });
  check(ini, "filter_sigma_range_m", [&] { localization::validate(cl.filter); });
  check(ini, "filter_sigma_angle_rad",  // e.g. a zero filter sigma (also found by fuzz_rawlog)
        [&] { cl.refinement = fusion::refinement_config_from(cl.filter.noise, sc.noise_variance()); });
  cl.refine = ini.get_bool(kLoop, "refine", cl.refine);
  cl.refinement.use_csi = ini.get_bool(kLoop, "use_csi", cl.refinement.use_csi);
  cl.refinement.window_epochs = static_cast<int>(
      ini.get_integer(kLoop, "window_epochs", cl.refinement.window_epochs, 1, 64));
  cl.fallback_to_bf = ini.get_bool(kLoop, "fallback", cl.fallback_to_bf);
  const std::string gd_mode = ini.get_string(kLoop, "gd_mode", to_string(cl.gd_mode));
  check(ini, "gd_mode", [&] { cl.gd_mode = fusion::gd_belief_mode_from_string(gd_mode); });
  if (ini.has(kLoop, "outages")) {
    cl.outages = parse_outages(ini.get_string(kLoop, "outages", ""), ini.where(kLoop, "outages"),
                               sc.num_uavs);
  }
  if (ini.has(kLoop, "faults")) {
    cl.faults = parse_faults(ini.get_string(kLoop, "faults", ""), ini.where(kLoop, "faults"),
                             sc.num_uavs);
  }
  cl.unresponsive_after_iterations = static_cast<int>(ini.get_integer(
      kLoop, "unresponsive_after_iterations", cl.unresponsive_after_iterations, 1, 1000));
  check(ini, "faults", [&] {  // e.g. nan_csi without refine and use_csi
    for (const fusion::UavFault& f : cl.faults) {
      if (f.kind == fusion::UavFaultKind::kNanCsi && !(cl.refine && cl.refinement.use_csi))
        throw std::invalid_argument("nan_csi needs refine = true and use_csi = true");
    }
  });
  check(ini, "refine", [&] { validate(cl); });

  c.seed = static_cast<std::uint64_t>(
      ini.get_integer(kMission, "seed", 1, 0, std::numeric_limits<long long>::max()));
  c.start_seed = static_cast<std::uint64_t>(
      ini.get_integer(kMission, "start_seed", 1, 0, std::numeric_limits<long long>::max()));
  c.epoch_period_s = ini.get_double(kMission, "epoch_period_s", c.epoch_period_s);
  if (!(c.epoch_period_s > 0.0 && c.epoch_period_s <= 86400.0)) {
    throw common::InputError(ini.where(kMission, "epoch_period_s") + ": must be in (0, 86400] s");
  }
  return c;
}

std::string mission_to_ini(const MissionConfig& c) {
  std::ostringstream o;
  o << std::setprecision(17);
  o << placement::to_ini(c.placement);
  const fusion::ClosedLoopConfig& cl = c.closed_loop;
  o << "\n[closed_loop]\n"
    << "filter = " << localization::to_string(cl.filter_kind) << "\n"
    << "num_particles = " << cl.filter.num_particles << "\n"
    << "refine = " << (cl.refine ? "true" : "false") << "\n"
    << "use_csi = " << (cl.refinement.use_csi ? "true" : "false") << "\n"
    << "window_epochs = " << cl.refinement.window_epochs << "\n"
    << "fallback = " << (cl.fallback_to_bf ? "true" : "false") << "\n"
    << "gd_mode = " << to_string(cl.gd_mode) << "\n"
    << "beacon_sigma_range_m = " << cl.simulator.sigma_range_m << "\n"
    << "beacon_sigma_angle_rad = " << cl.simulator.sigma_angle_rad << "\n"
    << "beacon_period_epochs = " << cl.simulator.beacon_period_epochs << "\n"
    << "outlier_fraction = " << cl.simulator.outlier_fraction << "\n"
    << "dr_sigma_floor_m = " << cl.simulator.dr_sigma_floor_m << "\n"
    << "dr_sigma_fraction = " << cl.simulator.dr_sigma_fraction << "\n"
    << "filter_sigma_range_m = " << cl.filter.noise.sigma_range_m << "\n"
    << "filter_sigma_angle_rad = " << cl.filter.noise.sigma_angle_rad << "\n"
    << "degraded_after_epochs = " << cl.filter.degraded_after_epochs << "\n"
    << "outages = ";
  for (std::size_t i = 0; i < cl.outages.size(); ++i) {
    const fusion::UavBeaconOutage& u = cl.outages[i];
    o << (i ? ", " : "") << u.uav << ":" << u.window.first_epoch << ":" << u.window.num_epochs;
  }
  // Fault keys only when set: the CONFIG of a mission without them stays as it was.
  if (!cl.faults.empty()) {
    o << "\nfaults = ";
    for (std::size_t i = 0; i < cl.faults.size(); ++i) {
      const fusion::UavFault& f = cl.faults[i];
      o << (i ? ", " : "") << to_string(f.kind) << ":" << f.uav << ":" << f.from_iteration << ":"
        << f.num_iterations;
    }
  }
  // Likewise the beacon range limit only when not the default.
  if (cl.filter.max_beacon_range_m != localization::FilterConfig{}.max_beacon_range_m)
    o << "\nfilter_max_beacon_range_m = " << cl.filter.max_beacon_range_m;
  if (!cl.faults.empty() || cl.unresponsive_after_iterations != fusion::ClosedLoopConfig{}.unresponsive_after_iterations)
    o << "\nunresponsive_after_iterations = " << cl.unresponsive_after_iterations;
  o << "\n\n[mission]\nseed = " << c.seed << "\nstart_seed = " << c.start_seed
    << "\nepoch_period_s = " << c.epoch_period_s << "\n";
  return o.str();
}

Eigen::Matrix3Xd mission_start_positions_m(const MissionConfig& config) {
  std::mt19937_64 rng(config.start_seed);
  return placement::random_start_positions_m(config.placement.scenario, rng);
}

}  // namespace losmimo::rawlog
