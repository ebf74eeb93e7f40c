// The co-evaluation's settings: its key table, reading, validation and serialisation
// (coevaluation.h).
#include <algorithm>
#include <limits>
#include <stdexcept>
#include <utility>

#include "losmimo/fusion/coevaluation/coevaluation.h"
#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/common/text.h"
#include "losmimo/fusion/closed_loop_settings.h"
#include "losmimo/localization/position/simulator.h"
#include "losmimo/placement/settings.h"

namespace losmimo::coevaluation {

namespace {

using common::InputError;
using common::split_list;
const std::string kSection = "coevaluation";

// "a, b, ..." rows (aliases or planner+estimator), at least one; resolved and checked by
// load_coevaluation_settings (resolve_rows), once ura_variant is known.
std::vector<CoevalRow> parse_rows(const std::string& text, const std::string& where) {
  std::vector<CoevalRow> out;
  for (const std::string& name : split_list(text)) out.push_back(parse_row(name, where));
  if (out.empty()) throw InputError(where + ": needs at least one algorithm");
  return out;
}

std::string row_list(const std::vector<CoevalRow>& rows) {
  return common::join_with(rows, [](const CoevalRow& r) { return r.name; });
}

std::string alias_list() {
  return common::join_with(row_aliases(), [](const RowAlias& a) { return a.alias; });
}

// The outage sweep runs gd's closed loop only: the point is what the fallback does.
void require_closed_loop(const std::vector<CoevalRow>& rows, const std::string& field) {
  for (const CoevalRow& r : rows) {
    if (r.planner != "gd" || !estimator_entry(r.estimator).closed_loop) {
      throw common::FieldError(
          field, r.name + ": the outage sweep runs gd's closed loop (gd with ekf, ekf_nofallback, pf or ekf_ceres)");
    }
  }
}

// The [closed_loop] keys the co-evaluation reads, with the spellings [coevaluation] had for them.
constexpr std::pair<const char*, const char*> kSharedClosedLoopKeys[] = {
    {"beacon_sigma_range_m", "sigma_range_m"},
    {"dr_sigma_floor_m", "dr_sigma_floor_m"},
    {"dr_sigma_fraction", "dr_sigma_fraction"},
    {"num_particles", "pf_particles"},
    {"window_epochs", "refine_window_epochs"},
    {"use_csi", "refine_use_csi"},
    // the common-mode beacon errors (no older spelling)
    {"bs_azimuth_bias_rad", nullptr},
    {"bs_elevation_bias_rad", nullptr},
    {"beacon_range_bias_m", nullptr},
    {"bs_position_error_m", nullptr}};

std::vector<common::Key<CoevaluationSettings>> coevaluation_key_list() {
  using K = common::Key<CoevaluationSettings>;
  std::vector<K> keys = {
      K::real_list(kSection, "beacon_noise_values_m", &CoevaluationSettings::beacon_noise_values_m,
                   common::Range::at_least(0.0), "beacon_noise_m sweep points [m]", "0, 0.05"),
      K::text(
          kSection, "algorithms",
          [](CoevaluationSettings& c, const std::string& text, const std::string& where) {
            c.algorithms = parse_rows(text, where);
          },
          [](const CoevaluationSettings& c) { return row_list(c.algorithms); },
          "comma-separated: " + alias_list() + ", or planner+estimator", "beacon_noise_m's rows (planner, estimator)",
          "gd_ekf, bf"),
      K::text(
          kSection, "ura_variant",
          [](CoevaluationSettings& c, const std::string& text, const std::string&) {
            if (text == "rigid") {
              c.ura_variant = placement::UraVariant::kRigid;
            } else if (text == "lattice") {
              c.ura_variant = placement::UraVariant::kLattice;
            } else {
              throw std::invalid_argument("'" + text + "': must be rigid or lattice");
            }
          },
          [](const CoevaluationSettings& c) {
            return std::string(c.ura_variant == placement::UraVariant::kRigid ? "rigid" : "lattice");
          },
          "rigid | lattice", "ura_ekf's URA (placement/ura.h)", "lattice"),
      K::integer_list(kSection, "outage_values", &CoevaluationSettings::outage_values, 0,
                      std::numeric_limits<int>::max(), "beacon_outage sweep points: UAVs without beacon", "0, 1"),
      K::text(
          kSection, "outage_algorithms",
          [](CoevaluationSettings& c, const std::string& text, const std::string& where) {
            c.outage_algorithms = parse_rows(text, where);
          },
          [](const CoevaluationSettings& c) { return row_list(c.outage_algorithms); },
          "comma-separated: gd_ekf, gd_ekf_nofallback, gd_pf, gd_ekf_ceres (gd with a filter estimator)",
          "beacon_outage's rows", "gd_pf"),
      K::integer(kSection, "outage_first_epoch", &CoevaluationSettings::outage_first_epoch, 0, 1'000'000,
                 "first epoch without beacon", "3"),
      K::integer(kSection, "outage_epochs", &CoevaluationSettings::outage_epochs, 0, 1'000'000, "epochs without beacon",
                 "7"),
      K::integer(kSection, "outage_degraded_after_epochs", &CoevaluationSettings::outage_degraded_after_epochs, 1,
                 1'000'000, "the filter is degraded after this many epochs without beacon", "2"),
      K::real(kSection, "outage_beacon_noise_m", &CoevaluationSettings::outage_beacon_noise_m,
              common::Range::at_least(0.0), "beacon cross-range 1-sigma at R in the outage sweep [m]", "0.05"),
      K::real_list(kSection, "misalignment_values_rad", &CoevaluationSettings::misalignment_values_rad,
                   localization::simulator_range::angle_bias,
                   "bs_misalignment_rad sweep points: the BS array's azimuth misalignment [rad]", "0, 0.0009765625"),
      K::text(
          kSection, "misalignment_algorithms",
          [](CoevaluationSettings& c, const std::string& text, const std::string& where) {
            c.misalignment_algorithms = parse_rows(text, where);
          },
          [](const CoevaluationSettings& c) { return row_list(c.misalignment_algorithms); },
          "comma-separated, as algorithms", "bs_misalignment_rad's rows", "gd_ekf, gd_gauss_shape_matched"),
      K::real(kSection, "misalignment_beacon_noise_m", &CoevaluationSettings::misalignment_beacon_noise_m,
              common::Range::at_least(0.0), "beacon cross-range 1-sigma at R in the misalignment sweep [m]", "0.03125"),
  };
  for (const auto& [key, old_key] : kSharedClosedLoopKeys) {
    const common::Key<fusion::ClosedLoopConfig>& shared = fusion::closed_loop_keys().key("closed_loop", key);
    keys.push_back(common::nested(shared, &CoevaluationSettings::closed_loop, "closed_loop"));
  }
  return keys;
}

}  // namespace

const common::KeyTable<CoevaluationSettings>& coevaluation_keys() {
  static const common::KeyTable<CoevaluationSettings> table = [] {
    common::KeyTable<CoevaluationSettings> t(coevaluation_key_list());
    for (const auto& [key, old_key] : kSharedClosedLoopKeys) {
      if (old_key) t.renamed(kSection, old_key, "closed_loop", key);
    }
    return t;
  }();
  return table;
}

std::map<std::string, std::set<std::string>> coevaluation_config_keys() { return coevaluation_keys().known_keys(); }

CoevaluationSettings load_coevaluation_settings(const experiment::ExperimentSettings& settings) {
  const common::IniConfig& cfg = settings.config;
  const placement::Scenario& scenario = settings.placement.scenario;
  const common::KeyTable<CoevaluationSettings>& keys = coevaluation_keys();
  register_coevaluation_planners();
  CoevaluationSettings c;
  keys.load(cfg, c);
  if (settings.sweep(kSweepBeaconNoise) || settings.sweep(kSweepBeaconOutage) || settings.sweep(kSweepMisalignment)) {
    placement::require_los_channel(settings.placement.channel, cfg, "co-evaluation");
  }
  // The sweeps that run any planner, with their rows.
  const std::pair<const std::string*, const std::vector<CoevalRow>*> planner_sweeps[] = {
      {&kSweepBeaconNoise, &c.algorithms}, {&kSweepMisalignment, &c.misalignment_algorithms}};
  // centralized solves eq. 4 for its target ICN alpha, which must be below 1 (fusion/centralized.h).
  for (const auto& [sweep, rows] : planner_sweeps) {
    const bool has_centralized =
        std::any_of(rows->begin(), rows->end(), [](const CoevalRow& r) { return r.planner == "centralized"; });
    if (settings.sweep(*sweep) && has_centralized && !(settings.placement.run.target_icn < 1.0)) {
      throw InputError(cfg.where("placement", "target_icn") + ": " +
                       common::format_double(settings.placement.run.target_icn) + ": the " + *sweep +
                       " sweep's centralized solution needs a target ICN below 1");
    }
  }
  keys.check(cfg, "", [&] {
    // The rows: ura_ekf's URA from ura_variant, every pair as its estimator allows.
    resolve_rows(c.algorithms, c.ura_variant, "algorithms");
    resolve_rows(c.outage_algorithms, c.ura_variant, "outage_algorithms");
    resolve_rows(c.misalignment_algorithms, c.ura_variant, "misalignment_algorithms");
    require_closed_loop(c.outage_algorithms, "outage_algorithms");
    // The shared closed-loop settings by the closed loop's own rules.
    common::with_field_prefix("closed_loop", [&] { fusion::validate(c.closed_loop); });
    for (const auto& [sweep, rows] : planner_sweeps) {
      for (const CoevalRow& row : *rows) {
        const std::vector<std::string>& own = placement::planner_entry(row.planner).sections;
        const bool ura = std::find(own.begin(), own.end(), "ura") != own.end();
        if (settings.sweep(*sweep) && ura && scenario.num_uavs != scenario.num_bs_antennas()) {
          throw common::FieldError(rows == &c.algorithms ? "algorithms" : "misalignment_algorithms",
                                   row.name + " needs scenario.num_uavs = bs_rows * bs_cols (" +
                                       std::to_string(scenario.num_bs_antennas()) + "), got " +
                                       std::to_string(scenario.num_uavs));
        }
      }
    }
    // Checked with or without the sweep when given; the default only when the sweep runs.
    if (cfg.has(kSection, "outage_values") || settings.sweep(kSweepBeaconOutage)) {
      for (const int k : c.outage_values) {
        if (k > scenario.num_uavs) {
          throw common::FieldError("outage_values", std::to_string(k) + " UAVs without beacon, but the swarm has " +
                                                        std::to_string(scenario.num_uavs));
        }
      }
    }
  });
  return c;
}

std::string to_ini(const CoevaluationSettings& c) { return coevaluation_keys().to_ini(c); }

const experiment::ExtensionMetrics& coevaluation_metrics() {
  static const experiment::ExtensionMetrics kTable = {
      kLocRmse, kLocLateralRmse,     kCommonLateral,     kShapeLateralRmse, kShapeNees,
      kNees,    kBfFallbackFraction, kBeaconLateralRmse, kPairedTravelDiff, kPairedIterationsDiff};
  return kTable;
}

}  // namespace losmimo::coevaluation
