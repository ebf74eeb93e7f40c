#include "losmimo/placement/settings.h"

#include <limits>
#include <utility>

namespace losmimo::placement {

namespace {

using common::Range;

// One table per section's struct; the rules beyond a key's own range are the struct's
// validate(), whose FieldError names the field (= the key here).
std::vector<common::Key<Scenario>> scenario_keys() {
  using K = common::Key<Scenario>;
  return {
      K::integer("scenario", "bs_rows", &Scenario::bs_rows, scenario_range::bs_rows, "BS array rows", "2"),
      K::integer("scenario", "bs_cols", &Scenario::bs_cols, scenario_range::bs_cols, "BS array columns", "8"),
      K::real("scenario", "bs_spacing_m", &Scenario::bs_spacing_m, scenario_range::bs_spacing_m,
              "BS antenna spacing [m]", "0.5"),
      K::real("scenario", "carrier_hz", &Scenario::carrier_hz, scenario_range::carrier_hz, "carrier frequency [Hz]",
              "3e+10"),
      K::integer("scenario", "num_uavs", &Scenario::num_uavs, scenario_range::num_uavs, "swarm size", "9"),
      K::real("scenario", "cube_side_m", &Scenario::cube_side_m, scenario_range::cube_side_m,
              "side of the start cube [m]", "20"),
      K::real(
          "scenario", "cube_center_x_m", [](auto& s) -> auto& { return s.cube_center_m.x(); },
          scenario_range::cube_center_m, "start cube centre x, along the link from the BS [m]", "500"),
      K::real(
          "scenario", "cube_center_y_m", [](auto& s) -> auto& { return s.cube_center_m.y(); },
          scenario_range::cube_center_m, "start cube centre y [m]", "10"),
      K::real(
          "scenario", "cube_center_z_m", [](auto& s) -> auto& { return s.cube_center_m.z(); },
          scenario_range::cube_center_m, "start cube centre z [m]", "-10"),
      K::real("scenario", "snr_db", &Scenario::snr_db, scenario_range::snr_db,
              "SNR per BS-antenna-to-UAV link at the swarm range [dB]", "20"),
      K::text(
          "scenario", "gain_model",
          [](Scenario& s, const std::string& text, const std::string&) { s.gain_model = gain_model_from_string(text); },
          [](const Scenario& s) { return to_string(s.gain_model); }, "far_field | exact",
          "channel amplitudes: far-field (the paper's) or exact per-antenna distances", "exact"),
  };
}

// A key whose value is one of an enum's names (to_string / from_string).
template <typename S, typename Field, typename From>
common::Key<S> choice(const std::string& section, const std::string& key, Field S::*field, From from_string,
                      const std::string& rule, const std::string& doc, const std::string& example) {
  return common::Key<S>::text(
             section, key,
             [field, from_string](S& s, const std::string& text, const std::string&) { s.*field = from_string(text); },
             [field](const S& s) { return to_string(s.*field); }, rule, doc, example)
      .unless_default();
}

std::vector<common::Key<ErrorModel>> error_keys() {
  using K = common::Key<ErrorModel>;
  return {
      K::real("errors", "sigma_loc_m", &ErrorModel::sigma_loc_m, error_range::sigma_loc_m,
              "localization error 1-sigma per axis [m]", "0.1"),
      K::real("errors", "sigma_act_m", &ErrorModel::sigma_act_m, error_range::sigma_act_m,
              "actuation error 1-sigma per axis [m]", "0.1"),
      choice("errors", "sigma_convention", &ErrorModel::sigma_convention, &sigma_convention_from_string,
             "per_axis | rms_3d", "the sigmas per axis, or the RMS length of the 3-D error (sigma / sqrt(3) per axis)",
             "rms_3d"),
      choice("errors", "loc_error", &ErrorModel::loc_error, &loc_error_from_string, "fresh | fixed_per_uav",
             "localization error drawn at every estimate, or once per UAV and run (a bias)", "fixed_per_uav"),
      K::real("errors", "sigma_loc_common_m", &ErrorModel::sigma_loc_common_m, error_range::sigma_loc_common_m,
              "common-mode localization error: 1-sigma per axis of one offset per run that every UAV's estimates "
              "share (a misaligned or mis-surveyed BS) [m]",
              "0.5")
          .unless_default(),
  };
}

std::vector<common::Key<RunOptions>> run_keys() {
  using K = common::Key<RunOptions>;
  return {
      K::real("placement", "target_icn", &RunOptions::target_icn, run_range::target_icn, "the run stops at this ICN",
              "0.9"),
      K::integer("placement", "max_iterations", &RunOptions::max_iterations,
                 // At least one: 0 only evaluates the start (a report's "iterations to ICN 0.95: 0").
                 common::Range::closed(1, run_range::max_iterations.hi), "the run stops after this many iterations",
                 "50"),
      choice("placement", "stop_on", &RunOptions::stop_on, &stop_on_from_string, "csi | belief",
             "the stop test's ICN: of the measured channel, or of the planner's believed positions", "belief"),
      choice("placement", "distance", &RunOptions::distance, &distance_kind_from_string, "true_path | commanded",
             "distances count the true path flown or the commanded moves", "commanded"),
      K::boolean("placement", "milestone_distance_includes_probes", &RunOptions::milestone_distance_includes_probes,
                 "the distance to ICN 0.5 / 0.95 counts BF's probe flights too", "true")
          .unless_default(),
  };
}

// The per-algorithm stop rules, one pair of keys per algorithm section.
std::vector<common::Key<RunOverride>> run_override_keys(const std::string& section) {
  using K = common::Key<RunOverride>;
  return {
      K::real(section, "target_icn", &RunOverride::target_icn, common::Range::closed(0.0, 1.0),
              "this algorithm's runs stop at this ICN; 0: [placement] target_icn", "1")
          .unless_default(),
      K::integer(section, "max_iterations", &RunOverride::max_iterations, -1, 10'000'000,
                 "this algorithm's runs stop after this many iterations; -1: [placement] max_iterations", "2000")
          .unless_default(),
  };
}

std::vector<common::Key<GdOptions>> gd_keys() {
  using K = common::Key<GdOptions>;
  return {
      K::real("gd", "step", &GdOptions::step, gd_range::step, "initial step, per unit gradient", "0.1"),
      K::real("gd", "decay", &GdOptions::decay, gd_range::decay, "step decay per iteration", "0.99"),
      K::real("gd", "max_move_m", &GdOptions::max_move_m, gd_range::max_move_m, "largest move per iteration [m]",
              "0.25"),
      K::boolean("gd", "backtracking", &GdOptions::backtracking, "halve a step that does not decrease f", "false"),
      K::integer("gd", "max_halvings", &GdOptions::max_halvings, gd_range::max_halvings, "halvings per backtracking",
                 "3"),
      K::boolean("gd", "escape", &GdOptions::escape, "lateral search of a stalled UAV (stall.h)", "false"),
      K::integer("gd", "stall_window", &GdOptions::stall_window, gd_range::stall_window, "stall window [iterations]",
                 "10"),
      K::real("gd", "stall_min_decrease", &GdOptions::stall_min_decrease, gd_range::stall_min_decrease,
              "stalled below this relative decrease of f over the window", "0.02"),
      // The large-swarm keys only when set, so that the defaults' text (paper.ini) is unchanged.
      K::integer("gd", "escape_half_grid", &GdOptions::escape_half_grid, gd_range::escape_half_grid,
                 "escape grid: (2 h + 1)^2 lateral points", "6")
          .unless_default(),
      K::integer("gd", "escape_uavs", &GdOptions::escape_uavs, gd_range::escape_uavs, "UAVs that search at each stall",
                 "2")
          .unless_default(),
      K::real("gd", "depth_step_gain", &GdOptions::depth_step_gain, gd_range::depth_step_gain,
              "multiplies the step's component along the link", "4")
          .unless_default(),
  };
}

std::vector<common::Key<BfOptions>> bf_keys() {
  using K = common::Key<BfOptions>;
  return {
      K::real("bf", "step", &BfOptions::step, bf_range::step, "initial probe step [m]", "0.2"),
      K::real("bf", "decay", &BfOptions::decay, bf_range::decay, "step decay per iteration", "0.99"),
      K::real("bf", "contraction", &BfOptions::contraction, bf_range::contraction,
              "step factor after a failed compass round", "0.25"),
      K::real("bf", "min_step_m", &BfOptions::min_step_m, bf_range::min_step_m, "smallest step [m]", "0.02"),
      K::boolean("bf", "escape", &BfOptions::escape, "lateral search of a stalled UAV (stall.h)", "false"),
      K::integer("bf", "stall_window", &BfOptions::stall_window, bf_range::stall_window, "stall window [iterations]",
                 "10"),
      K::real("bf", "stall_min_decrease", &BfOptions::stall_min_decrease, bf_range::stall_min_decrease,
              "stalled below this relative decrease of f over the window", "0.02"),
      choice("bf", "probe_actuation", &BfOptions::probe_actuation, &probe_actuation_from_string,
             "every_leg | kept_move_only",
             "actuation error on every probe flight, or on the kept move only (probes exact)", "kept_move_only"),
  };
}

std::vector<common::Key<UraOptions>> ura_keys() {
  using K = common::Key<UraOptions>;
  return {
      K::integer("ura", "spacing_multiple", &UraOptions::spacing_multiple, 1, 64,
                 "URA spacing in units of lambda x / (n d_t); coprime with the BS rows and columns", "3")
          .unless_default(),
      choice("ura", "depth", &UraOptions::depth, &ura_depth_from_string, "plane | own",
             "rigid URA slots at the cube centre's depth, or at the assigned UAV's own depth", "own"),
      choice("ura", "retry", &UraOptions::retry, &ura_retry_from_string, "every_iteration | once | average",
             "URA moves: re-aimed at every iteration, commanded once, or from the mean of the estimates", "once"),
  };
}

// [cap]: every key only written when set, so that the defaults' text (paper.ini) is unchanged.
std::vector<common::Key<CapOptions>> cap_keys() {
  using K = common::Key<CapOptions>;
  return {
      K::real("cap", "step", &CapOptions::step, cap_range::step,
              "initial step per unit capacity gradient [m^2 per bit/s/Hz]", "0.5")
          .unless_default(),
      K::real("cap", "decay", &CapOptions::decay, cap_range::decay, "step decay per iteration", "0.99")
          .unless_default(),
      K::real("cap", "max_move_m", &CapOptions::max_move_m, cap_range::max_move_m, "largest move per iteration [m]",
              "0.25")
          .unless_default(),
      K::boolean("cap", "backtracking", &CapOptions::backtracking,
                 "halve a step that decreases the capacity (the UAV stays if none increases it)", "false")
          .unless_default(),
      K::integer("cap", "max_halvings", &CapOptions::max_halvings, cap_range::max_halvings, "halvings per backtracking",
                 "3")
          .unless_default(),
      choice("cap", "power", &CapOptions::power, &cap_power_from_string, "equal | waterfill",
             "the capacity climbed: equal power per BS antenna, or water-filling over the channel's modes",
             "waterfill"),
  };
}

// [channel]: off (inf) by default; each key only written when set, so that every config and
// recorded mission without them keeps its text.
std::vector<common::Key<ChannelSettings>> channel_keys() {
  using K = common::Key<ChannelSettings>;
  const auto db_key = [](const std::string& key, double ChannelSettings::*field, double lo, double hi,
                         const std::string& doc, const std::string& example) {
    K k = K::text(
        "channel", key,
        [field, lo, hi](ChannelSettings& c, const std::string& text, const std::string& where) {
          c.*field = parse_db_or_inf(text, where, lo, hi);
        },
        [field](const ChannelSettings& c) { return format_db_or_inf(c.*field); },
        "dB in [" + common::format_double(lo) + ", " + common::format_double(hi) + "], or inf", doc, example);
    k.refused = {"nan", "-inf", "not-a-number", common::format_double(lo - 1.0), common::format_double(hi + 1.0)};
    return std::move(k).unless_default();
  };
  return {
      db_key("rician_k_db", &ChannelSettings::rician_k_db, kMinRicianK_db, kMaxRicianK_db,
             "Rician K-factor: LoS over scattered power (docs/model.md); inf = pure LoS", "10"),
      K::integer("channel", "coherence_iterations", &ChannelSettings::coherence_iterations, 1, kMaxCoherenceIterations,
                 "iterations per draw of the scattered component (block fading)", "5")
          .unless_default(),
      db_key("csi_snr_db", &ChannelSettings::csi_snr_db, kMinCsiSnr_db, kMaxCsiSnr_db,
             "SNR of the measured channel per entry (pilot estimate); inf = perfect CSI", "20"),
      K::integer("channel", "fading_eval_draws", &ChannelSettings::fading_eval_draws, 1, kMaxFadingEvalDraws,
                 "scatter draws averaged by the final metrics when rician_k_db is finite", "50")
          .unless_default(),
  };
}

template <typename Inner>
void append(std::vector<common::Key<PlacementSettings>>& keys, const std::vector<common::Key<Inner>>& inner,
            Inner PlacementSettings::*member, const std::string& member_name) {
  for (auto& k : common::nested(inner, member, member_name)) keys.push_back(std::move(k));
}

}  // namespace

const common::KeyTable<PlacementSettings>& placement_keys() {
  static const common::KeyTable<PlacementSettings> table = [] {
    std::vector<common::Key<PlacementSettings>> keys;
    append(keys, scenario_keys(), &PlacementSettings::scenario, "scenario");
    append(keys, error_keys(), &PlacementSettings::errors, "errors");
    append(keys, run_keys(), &PlacementSettings::run, "run");
    append(keys, gd_keys(), &PlacementSettings::gd, "gd");
    append(keys, run_override_keys("gd"), &PlacementSettings::gd_run, "gd_run");
    append(keys, bf_keys(), &PlacementSettings::bf, "bf");
    append(keys, run_override_keys("bf"), &PlacementSettings::bf_run, "bf_run");
    append(keys, ura_keys(), &PlacementSettings::ura, "ura");
    append(keys, run_override_keys("ura"), &PlacementSettings::ura_run, "ura_run");
    append(keys, channel_keys(), &PlacementSettings::channel, "channel");
    append(keys, cap_keys(), &PlacementSettings::cap, "cap");
    append(keys, run_override_keys("cap"), &PlacementSettings::cap_run, "cap_run");
    return common::KeyTable<PlacementSettings>(std::move(keys));
  }();
  return table;
}

std::map<std::string, std::set<std::string>> placement_config_keys() { return placement_keys().known_keys(); }

PlacementSettings load_placement_settings(const common::IniConfig& cfg) {
  const common::KeyTable<PlacementSettings>& keys = placement_keys();
  PlacementSettings s;
  keys.load(cfg, s);
  s.run.noise_variance = s.scenario.noise_variance();
  keys.check(cfg, "scenario", [&] { validate(s.scenario); });
  keys.check(cfg, "errors", [&] { validate(s.errors); });
  keys.check(cfg, "run", [&] { validate(s.run); });
  keys.check(cfg, "gd", [&] { validate(s.gd); });
  keys.check(cfg, "bf", [&] { validate(s.bf); });
  keys.check(cfg, "ura", [&] { validate(s.ura, s.scenario); });
  keys.check(cfg, "channel", [&] { validate(s.channel); });
  keys.check(cfg, "cap", [&] { validate(s.cap); });
  return s;
}

RunOptions with_override(RunOptions run, const RunOverride& o) {
  if (o.target_icn > 0.0) run.target_icn = o.target_icn;
  if (o.max_iterations >= 0) run.max_iterations = o.max_iterations;
  return run;
}

void require_los_channel(const ChannelSettings& channel, const common::IniConfig& config, const std::string& tool) {
  const auto refuse = [&](const std::string& key, double value) {
    throw common::InputError(config.where("channel", key) + ": " + format_db_or_inf(value) + " is not supported by " +
                             tool + ", which models the LoS channel with perfect CSI (use losmimo-experiment)");
  };
  if (channel.fading()) refuse("rician_k_db", channel.rician_k_db);
  if (channel.noisy_csi()) refuse("csi_snr_db", channel.csi_snr_db);
}

std::string to_ini(const PlacementSettings& settings) { return placement_keys().to_ini(settings); }

}  // namespace losmimo::placement
