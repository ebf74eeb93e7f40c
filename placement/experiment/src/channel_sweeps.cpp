// The channel sweeps' keys and trials (channel_sweeps.h); figures and report in channel_report.cpp.
#include "losmimo/placement/experiment/channel_sweeps.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/channel_conditions.h"

namespace losmimo::experiment {

namespace {

const std::string kSection = "experiment";
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A list of dB levels, each in [lo, hi] or inf.
common::Key<ChannelSweepSettings> db_list(const std::string& key, std::vector<double> ChannelSweepSettings::*field,
                                          double lo, double hi, const std::string& doc, const std::string& example) {
  using K = common::Key<ChannelSweepSettings>;
  K k = K::text(
      kSection, key,
      [field, lo, hi](ChannelSweepSettings& s, const std::string& text, const std::string& where) {
        std::vector<double> values;
        for (const std::string& item : common::split_list(text)) {
          values.push_back(placement::parse_db_or_inf(item, where, lo, hi));
        }
        if (values.empty()) throw common::InputError(where + ": needs at least one value");
        s.*field = values;
      },
      [field](const ChannelSweepSettings& s) {
        std::string out;
        for (const double v : s.*field) out += (out.empty() ? "" : ", ") + placement::format_db_or_inf(v);
        return out;
      },
      "comma-separated dB in [" + common::format_double(lo) + ", " + common::format_double(hi) + "], or inf", doc,
      example);
  k.refused = {"", "nan", "-inf", "0, not-a-number", common::format_double(lo - 1.0), common::format_double(hi + 1.0)};
  return k;
}

std::vector<common::Key<ChannelSweepSettings>> channel_sweep_key_list() {
  using K = common::Key<ChannelSweepSettings>;
  return {
      db_list("rician_k_db_values", &ChannelSweepSettings::rician_k_db_values, placement::kMinRicianK_db,
              placement::kMaxRicianK_db, "sweep points of rician_k_db: the Rician K-factor [dB] (inf: pure LoS)",
              "0, 10, inf"),
      db_list("csi_snr_db_values", &ChannelSweepSettings::csi_snr_db_values, placement::kMinCsiSnr_db,
              placement::kMaxCsiSnr_db, "sweep points of csi_snr_db: the CSI estimation SNR [dB] (inf: perfect CSI)",
              "20, inf"),
      K::integer_list(kSection, "bs_antennas_values", &ChannelSweepSettings::bs_antennas_values, 1, 4096,
                      "sweep points of bs_antennas: BS antennas n^2 of an n x n array (perfect squares)", "16, 64"),
  };
}

bool runs_a_ura(const ExperimentSettings& s) {
  return std::any_of(s.algorithms.begin(), s.algorithms.end(), [](const Algorithm& a) {
    return a == Algorithm::kUra || a == Algorithm::kUraLattice || a == Algorithm::kUraLatticeExact;
  });
}

int array_side(int antennas) { return static_cast<int>(std::lround(std::sqrt(static_cast<double>(antennas)))); }

}  // namespace

const common::KeyTable<ChannelSweepSettings>& channel_sweep_keys() {
  static const common::KeyTable<ChannelSweepSettings> table(channel_sweep_key_list());
  return table;
}

ChannelSweepSettings load_channel_sweep_settings(const ExperimentSettings& s) {
  const common::KeyTable<ChannelSweepSettings>& keys = channel_sweep_keys();
  ChannelSweepSettings c;
  keys.load(s.config, c);
  if (s.sweep(kSweepBsAntennas)) {
    const std::string where = s.config.where(kSection, "bs_antennas_values");
    for (const int n : c.bs_antennas_values) {
      const int side = array_side(n);
      if (side * side != n || side > 64) {
        throw common::InputError(where + ": " + std::to_string(n) +
                                 " is not the antenna count of a square array n x n with n in [1, 64]");
      }
      if (runs_a_ura(s) && n < s.placement.scenario.num_uavs) {
        throw common::InputError(where + ": " + std::to_string(n) +
                                 " antennas < scenario.num_uavs = " + std::to_string(s.placement.scenario.num_uavs) +
                                 ": a URA needs a slot per UAV (drop the ura algorithms or the value)");
      }
    }
  }
  return c;
}

const ExtensionMetrics& channel_sweep_metrics() {
  static const ExtensionMetrics kTable = {kFinalIcnLos, kFinalIcnMeasured, kSumRateNvLosBpsHz, kSumRateZfLosBpsHz};
  return kTable;
}

std::vector<TrialRecord> run_channel_sweep_trial(const ExperimentSettings& s, const std::string& sweep, int point,
                                                 int trial) {
  placement::PlacementSettings p = s.placement;
  const double value = s.sweep(sweep)->values.at(point);
  if (sweep == kSweepRicianK) {
    p.channel.rician_k_db = value;
  } else if (sweep == kSweepCsiSnr) {
    p.channel.csi_snr_db = value;
  } else if (sweep == kSweepBsAntennas) {
    p.scenario.bs_rows = p.scenario.bs_cols = array_side(static_cast<int>(value));
  } else {
    throw std::invalid_argument("run_channel_sweep_trial: '" + sweep + "' is not a channel sweep");
  }
  const Eigen::Matrix3Xd start = trial_start_positions_m(s, trial);
  const std::uint64_t seed = trial_seed(s, sweep, point, trial);
  placement::RunOptions run = p.run;
  run.full_icn_trace = false;  // only milestones and the final positions are recorded
  std::vector<TrialRecord> records;
  for (const Algorithm& a : s.algorithms) {
    const placement::RunResult r = run_algorithm(s, p, a, trial, start, seed, run);
    placement::FadedLinkMetrics m;
    TrialRecord rec = make_record(s, p, sweep, point, trial, to_string(a), r, &m);
    // The stop test's last value: measured CSI (= the LoS channel without conditions).
    const double measured = p.channel.active() ? (r.trace.empty() ? kNaN : r.trace.back().icn) : m.los.icn;
    rec.extension.set(kFinalIcnLos, m.los.icn);
    rec.extension.set(kFinalIcnMeasured, measured);
    rec.extension.set(kSumRateNvLosBpsHz, m.los.sum_rate_nv_bps_hz);
    rec.extension.set(kSumRateZfLosBpsHz, m.los.sum_rate_zf_bps_hz);
    records.push_back(std::move(rec));
  }
  return records;
}

ExperimentExtensions channel_sweep_extensions() {
  ExperimentExtensions out;
  for (const std::string& sweep : {kSweepRicianK, kSweepCsiSnr, kSweepBsAntennas}) {
    ExperimentExtension e;
    e.sweep = sweep;
    e.config_keys = channel_sweep_keys().known_keys();
    e.metrics = channel_sweep_metrics();
    e.load_values = [sweep](const ExperimentSettings& s) {
      const ChannelSweepSettings c = load_channel_sweep_settings(s);
      if (sweep == kSweepRicianK) return c.rician_k_db_values;
      if (sweep == kSweepCsiSnr) return c.csi_snr_db_values;
      return std::vector<double>(c.bs_antennas_values.begin(), c.bs_antennas_values.end());
    };
    e.run = [sweep](const ExperimentSettings& s, int point, int trial) {
      return run_channel_sweep_trial(s, sweep, point, trial);
    };
    e.figures = [sweep](const ExperimentSettings& s, const std::vector<SummaryRow>& rows, const std::string& dir) {
      return write_channel_sweep_figure(s, sweep, rows, dir);
    };
    e.report_section = [sweep](const ExperimentSettings& s, const std::vector<SummaryRow>& rows) {
      return channel_sweep_report_section(s, sweep, rows);
    };
    out.push_back(std::move(e));
  }
  return out;
}

}  // namespace losmimo::experiment
