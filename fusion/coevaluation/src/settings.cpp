// [coevaluation]: reading, validation and serialisation (coevaluation.h).
#include <algorithm>
#include <cmath>
#include <sstream>

#include "losmimo/coevaluation/coevaluation.h"
#include "losmimo/common/format.h"
#include "losmimo/common/ini_config.h"
#include "losmimo/common/input_error.h"

namespace losmimo::coevaluation {

namespace {

using common::InputError;
using common::split_list;
const std::string kSection = "coevaluation";

constexpr CoevalAlgorithm kAll[] = {
    CoevalAlgorithm::kGdGauss, CoevalAlgorithm::kGdEkf,  CoevalAlgorithm::kGdEkfNoFallback,
    CoevalAlgorithm::kGdPf,    CoevalAlgorithm::kGdEkfCeres, CoevalAlgorithm::kBf,
    CoevalAlgorithm::kUraEkf,  CoevalAlgorithm::kCentralized};
// The outage sweep runs the closed loop only: the point is what the fallback does.
constexpr CoevalAlgorithm kOutageAllowed[] = {CoevalAlgorithm::kGdEkf, CoevalAlgorithm::kGdEkfNoFallback,
                                              CoevalAlgorithm::kGdPf, CoevalAlgorithm::kGdEkfCeres};

std::string names(const CoevalAlgorithm* first, const CoevalAlgorithm* last) {
  std::string out;
  for (const CoevalAlgorithm* a = first; a != last; ++a) out += (out.empty() ? "" : ", ") + to_string(*a);
  return out;
}

template <std::size_t N>
std::vector<CoevalAlgorithm> parse_algorithms(const common::IniConfig& cfg, const std::string& key,
                                              const CoevalAlgorithm (&allowed)[N],
                                              const std::vector<CoevalAlgorithm>& fallback) {
  if (!cfg.has(kSection, key)) return fallback;
  const std::string where = cfg.where(kSection, key);
  std::vector<CoevalAlgorithm> out;
  for (const std::string& name : common::split_list(cfg.get_string(kSection, key, ""))) {
    const auto* it = std::find_if(std::begin(allowed), std::end(allowed),
                                  [&](CoevalAlgorithm a) { return to_string(a) == name; });
    if (it == std::end(allowed)) {
      throw common::InputError(where + ": unknown algorithm '" + name + "' (known: " +
                       names(std::begin(allowed), std::end(allowed)) + ")");
    }
    if (std::find(out.begin(), out.end(), *it) != out.end())
      throw common::InputError(where + ": algorithm '" + name + "' listed twice");
    out.push_back(*it);
  }
  if (out.empty()) throw common::InputError(where + ": needs at least one algorithm");
  return out;
}

double non_negative(const common::IniConfig& cfg, const std::string& key, double fallback, bool positive) {
  const double v = cfg.get_double(kSection, key, fallback);
  if (positive ? !(v > 0.0) : !(v >= 0.0)) {
    throw common::InputError(cfg.where(kSection, key) + " = " + common::format_double(v) + ": must be " +
                     (positive ? "> 0" : ">= 0"));
  }
  return v;
}

std::string join(const std::vector<double>& v) {
  std::string out;
  for (double x : v) out += (out.empty() ? "" : ", ") + common::format_double(x);
  return out;
}

}  // namespace

std::string to_string(CoevalAlgorithm a) {
  switch (a) {
    case CoevalAlgorithm::kGdGauss: return "gd_gauss";
    case CoevalAlgorithm::kGdEkf: return "gd_ekf";
    case CoevalAlgorithm::kGdEkfNoFallback: return "gd_ekf_nofallback";
    case CoevalAlgorithm::kGdPf: return "gd_pf";
    case CoevalAlgorithm::kGdEkfCeres: return "gd_ekf_ceres";
    case CoevalAlgorithm::kBf: return "bf";
    case CoevalAlgorithm::kUraEkf: return "ura_ekf";
    case CoevalAlgorithm::kCentralized: return "centralized";
  }
  return "?";
}

std::map<std::string, std::set<std::string>> coevaluation_config_keys() {
  return {{kSection,
           {"beacon_noise_values_m", "algorithms", "sigma_range_m", "dr_sigma_floor_m", "dr_sigma_fraction",
            "pf_particles", "refine_window_epochs", "refine_use_csi", "ura_variant", "outage_values",
            "outage_algorithms", "outage_first_epoch", "outage_epochs", "outage_degraded_after_epochs",
            "outage_beacon_noise_m"}}};
}

CoevaluationSettings load_coevaluation_settings(const experiment::ExperimentSettings& settings) {
  const common::IniConfig& cfg = settings.config;
  const placement::Scenario& scenario = settings.placement.scenario;
  CoevaluationSettings c;

  if (cfg.has(kSection, "beacon_noise_values_m")) {
    const std::string where = cfg.where(kSection, "beacon_noise_values_m");
    c.beacon_noise_values_m.clear();
    for (const std::string& item : common::split_list(cfg.get_string(kSection, "beacon_noise_values_m", ""))) {
      const double v = common::parse_double(item, where);
      if (v < 0.0) throw common::InputError(where + ": " + item + " must be >= 0");
      c.beacon_noise_values_m.push_back(v);
    }
    if (c.beacon_noise_values_m.empty()) throw common::InputError(where + ": needs at least one value");
  }
  c.algorithms = parse_algorithms(cfg, "algorithms", kAll, c.algorithms);
  c.sigma_range_m = non_negative(cfg, "sigma_range_m", c.sigma_range_m, false);
  c.dr_sigma_floor_m = non_negative(cfg, "dr_sigma_floor_m", c.dr_sigma_floor_m, true);
  c.dr_sigma_fraction = non_negative(cfg, "dr_sigma_fraction", c.dr_sigma_fraction, false);
  c.pf_particles = static_cast<int>(cfg.get_integer(kSection, "pf_particles", c.pf_particles, 10, 1'000'000));
  c.refine_window_epochs =
      static_cast<int>(cfg.get_integer(kSection, "refine_window_epochs", c.refine_window_epochs, 1, 64));
  c.refine_use_csi = cfg.get_bool(kSection, "refine_use_csi", c.refine_use_csi);
  if (cfg.has(kSection, "ura_variant")) {
    const std::string v = cfg.get_string(kSection, "ura_variant", "");
    if (v == "rigid") {
      c.ura_variant = placement::UraVariant::kRigid;
    } else if (v == "lattice") {
      c.ura_variant = placement::UraVariant::kLattice;
    } else {
      throw common::InputError(cfg.where(kSection, "ura_variant") + " = '" + v + "': must be rigid or lattice");
    }
  }
  const bool has_ura = std::find(c.algorithms.begin(), c.algorithms.end(), CoevalAlgorithm::kUraEkf) != c.algorithms.end();
  if (settings.sweep(kSweepBeaconNoise) && has_ura && scenario.num_uavs != scenario.num_bs_antennas()) {
    throw common::InputError(cfg.where(kSection, "algorithms") + ": ura_ekf needs scenario.num_uavs = bs_rows * bs_cols (" +
                     std::to_string(scenario.num_bs_antennas()) + "), got " + std::to_string(scenario.num_uavs));
  }

  if (cfg.has(kSection, "outage_values")) {
    const std::string where = cfg.where(kSection, "outage_values");
    c.outage_values.clear();
    for (const std::string& item : common::split_list(cfg.get_string(kSection, "outage_values", ""))) {
      c.outage_values.push_back(static_cast<int>(common::parse_integer(item, where, 0, scenario.num_uavs)));
    }
    if (c.outage_values.empty()) throw common::InputError(where + ": needs at least one value");
  } else if (settings.sweep(kSweepBeaconOutage)) {
    for (const int k : c.outage_values) {
      if (k > scenario.num_uavs) {
        throw common::InputError("[coevaluation] outage_values (default) has " + std::to_string(k) + " UAVs but the swarm has " +
                         std::to_string(scenario.num_uavs) + ": set outage_values");
      }
    }
  }
  c.outage_algorithms = parse_algorithms(cfg, "outage_algorithms", kOutageAllowed, c.outage_algorithms);
  c.outage_first_epoch =
      static_cast<int>(cfg.get_integer(kSection, "outage_first_epoch", c.outage_first_epoch, 0, 1'000'000));
  c.outage_epochs = static_cast<int>(cfg.get_integer(kSection, "outage_epochs", c.outage_epochs, 0, 1'000'000));
  c.outage_degraded_after_epochs = static_cast<int>(
      cfg.get_integer(kSection, "outage_degraded_after_epochs", c.outage_degraded_after_epochs, 1, 1'000'000));
  c.outage_beacon_noise_m = non_negative(cfg, "outage_beacon_noise_m", c.outage_beacon_noise_m, false);
  return c;
}

std::string to_ini(const CoevaluationSettings& c) {
  const auto algorithm_list = [](const std::vector<CoevalAlgorithm>& v) {
    std::string out;
    for (const CoevalAlgorithm a : v) out += (out.empty() ? "" : ", ") + to_string(a);
    return out;
  };
  std::string outages;
  for (const int k : c.outage_values) outages += (outages.empty() ? "" : ", ") + std::to_string(k);
  std::ostringstream o;
  o << "[coevaluation]\n"
    << "beacon_noise_values_m = " << join(c.beacon_noise_values_m) << "\n"
    << "algorithms = " << algorithm_list(c.algorithms) << "\n"
    << "sigma_range_m = " << common::format_double(c.sigma_range_m) << "\n"
    << "dr_sigma_floor_m = " << common::format_double(c.dr_sigma_floor_m) << "\n"
    << "dr_sigma_fraction = " << common::format_double(c.dr_sigma_fraction) << "\n"
    << "pf_particles = " << c.pf_particles << "\n"
    << "refine_window_epochs = " << c.refine_window_epochs << "\n"
    << "refine_use_csi = " << (c.refine_use_csi ? "true" : "false") << "\n"
    << "ura_variant = " << (c.ura_variant == placement::UraVariant::kRigid ? "rigid" : "lattice") << "\n"
    << "outage_values = " << outages << "\n"
    << "outage_algorithms = " << algorithm_list(c.outage_algorithms) << "\n"
    << "outage_first_epoch = " << c.outage_first_epoch << "\n"
    << "outage_epochs = " << c.outage_epochs << "\n"
    << "outage_degraded_after_epochs = " << c.outage_degraded_after_epochs << "\n"
    << "outage_beacon_noise_m = " << common::format_double(c.outage_beacon_noise_m) << "\n";
  return o.str();
}

const std::vector<std::string>& coevaluation_extra_metrics() {
  static const std::vector<std::string> kNames = {"loc_rmse_m", "loc_lateral_rmse_m", "nees", "bf_fallback_fraction",
                                                  "beacon_lateral_rmse_m"};
  return kNames;
}

}  // namespace losmimo::coevaluation
