// The golden missions' invariants (datasets/missions/<mission>/invariants.ini), checked on a fresh
// replay of each mission.rawlog with each golden estimator, without reading golden/: what the
// golden outputs must mean, not what they were. Format and the reason of every bound:
// docs/rawlog-format.md#golden-missions.
//
// invariants.ini: INI sections [mission] (bounds of every variant) and optionally [<variant>]
// (e.g. [ekf+ceres]: overrides for that variant); every `key = value` line has its reason on the
// comment line(s) right above it. [mission] variants lists the golden/ folders. Keys (all
// required; an unknown key is an error, so that a typo cannot switch a check off):
//   status                    END_OF_LOG status of the recorded run (converged, iteration_cap)
//   epochs                    epochs of the recorded trajectory (the counts below are for it)
//   final_icn_min, _max       ICN at the final true positions
//   nees_epoch_low, _high     band of each epoch's average NEES over the swarm's UAVs
//   nees_epoch_min_fraction   fraction of the epochs whose average must be inside that band
//   nees_mean_low, _high      band of the average NEES over every UAV-epoch
//   range_rmse_min_m          RMSE along the line of sight (x) over the UAV-epochs with a beacon
//   rmse_max_m                3-D RMSE over the UAV-epochs with a beacon
//   beacons                   beacons the estimator consumed, exactly
//   fallback_fraction_min, _max   BF fallback UAV-epochs / (epochs x UAVs)
//
// LOSMIMO_GOLDEN_MISSIONS=DIR checks DIR/<mission>/{mission.rawlog, invariants.ini} instead of
// datasets/missions (scripts/regenerate-golden runs the Missions/* cases on its candidates).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Cholesky>

#include "losmimo/placement/channel.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/rawlog/replay.h"
#include "rawlog/rawlog_test_util.h"
#include "support/chi_square.h"

namespace losmimo::rawlog {
namespace {

using test_support::load_log;
using test_support::source_path;

// ---------------------------------------------------------------------------------------------
// invariants.ini

struct Bound {
  std::string value;
  std::string reason;
  int line = 0;
};
using Bounds = std::map<std::string, Bound>;  // key -> bound

struct InvariantsFile {
  std::string path;
  std::map<std::string, Bounds> sections;
  std::vector<std::string> problems;  // malformed lines, keys without a reason, duplicates
};

const std::vector<std::string>& variant_keys() {
  static const std::vector<std::string> keys = {"status",
                                                "epochs",
                                                "final_icn_min",
                                                "final_icn_max",
                                                "nees_epoch_low",
                                                "nees_epoch_high",
                                                "nees_epoch_min_fraction",
                                                "nees_mean_low",
                                                "nees_mean_high",
                                                "range_rmse_min_m",
                                                "rmse_max_m",
                                                "beacons",
                                                "fallback_fraction_min",
                                                "fallback_fraction_max"};
  return keys;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

InvariantsFile read_invariants(const std::string& path) {
  InvariantsFile f;
  f.path = path;
  std::ifstream in(path);
  if (!in) {
    f.problems.push_back(path + ": cannot be read");
    return f;
  }
  std::string section, reason;
  int n = 0;
  for (std::string raw; std::getline(in, raw);) {
    ++n;
    const std::string line = trim(raw);
    const std::string where = path + ":" + std::to_string(n);
    if (line.empty()) {
      reason.clear();  // a reason belongs to the key right below it
    } else if (line[0] == '#') {
      reason += (reason.empty() ? "" : " ") + trim(line.substr(1));
    } else if (line.front() == '[' && line.back() == ']') {
      section = trim(line.substr(1, line.size() - 2));
      f.sections[section];
      reason.clear();
    } else if (const auto eq = line.find('='); eq != std::string::npos && !section.empty()) {
      const std::string key = trim(line.substr(0, eq));
      if (reason.empty()) f.problems.push_back(where + ": " + key + " has no reason (a comment line right above it)");
      if (!f.sections[section].emplace(key, Bound{trim(line.substr(eq + 1)), reason, n}).second)
        f.problems.push_back(where + ": " + key + " given twice in [" + section + "]");
      reason.clear();
    } else {
      f.problems.push_back(where + ": not a [section], # comment or key = value in a section: " + line);
    }
  }
  return f;
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    if (!trim(item).empty()) out.push_back(trim(item));
  return out;
}

std::vector<std::string> listed_variants(const InvariantsFile& f) {
  const auto m = f.sections.find("mission");
  if (m == f.sections.end() || !m->second.count("variants")) return {};
  return split_list(m->second.at("variants").value);
}

// [mission]'s bounds with [variant]'s on top.
Bounds bounds_of(const InvariantsFile& f, const std::string& variant) {
  Bounds b;
  if (const auto m = f.sections.find("mission"); m != f.sections.end()) b = m->second;
  b.erase("variants");
  if (const auto v = f.sections.find(variant); v != f.sections.end())
    for (const auto& [key, bound] : v->second) b[key] = bound;
  return b;
}

// ---------------------------------------------------------------------------------------------
// What a replay shows, computed from its per-UAV estimates (never from golden/ or summary rows).

struct ReplayFigures {
  std::string status;  // END_OF_LOG
  int epochs = 0;
  int uavs = 0;
  double final_icn = 0.0;
  std::vector<double> epoch_average_nees;  // per epoch, over the UAVs with truth
  std::vector<int> epoch_nees_samples;
  double average_nees = 0.0;  // over every UAV-epoch with truth
  double range_rmse_m = 0.0;  // x error, UAV-epochs with a beacon
  double rmse_m = 0.0;        // 3-D, UAV-epochs with a beacon
  int beacons = 0;
  double fallback_fraction = 0.0;
};

ReplayFigures figures_of(const MissionLog& log, const ReplayResult& r) {
  ReplayFigures f;
  f.status = log.run_end.status;
  f.epochs = static_cast<int>(log.epochs.size());
  f.uavs = log.num_uavs;
  f.final_icn = r.final_icn;
  f.epoch_average_nees.assign(f.epochs, 0.0);
  f.epoch_nees_samples.assign(f.epochs, 0);
  double nees_sum = 0.0, x_sq = 0.0, sq = 0.0;
  int nees_n = 0;
  for (const ReplayUavEpoch& e : r.estimates) {
    if (e.has_beacon) ++f.beacons;
    if (!e.has_truth) continue;
    const Eigen::Vector3d err_m = e.belief.mean_m - e.truth_m;
    const double nees = err_m.dot(e.belief.cov_m2.ldlt().solve(err_m));
    f.epoch_average_nees[e.epoch] += nees;
    ++f.epoch_nees_samples[e.epoch];
    nees_sum += nees;
    ++nees_n;
    if (e.has_beacon) {
      x_sq += err_m.x() * err_m.x();
      sq += err_m.squaredNorm();
    }
  }
  for (int k = 0; k < f.epochs; ++k)
    if (f.epoch_nees_samples[k] > 0) f.epoch_average_nees[k] /= f.epoch_nees_samples[k];
  f.average_nees = nees_n > 0 ? nees_sum / nees_n : std::nan("");
  f.range_rmse_m = f.beacons > 0 ? std::sqrt(x_sq / f.beacons) : std::nan("");
  f.rmse_m = f.beacons > 0 ? std::sqrt(sq / f.beacons) : std::nan("");
  f.fallback_fraction = static_cast<double>(r.fallback_uav_epochs) / (static_cast<double>(f.epochs) * f.uavs);
  return f;
}

// ---------------------------------------------------------------------------------------------
// The checker: one message per violated (or missing, unknown, malformed) invariant.

std::vector<std::string> violations(const Bounds& bounds, const ReplayFigures& f) {
  std::vector<std::string> out;
  const std::set<std::string> known(variant_keys().begin(), variant_keys().end());
  for (const auto& [key, b] : bounds)
    if (!known.count(key)) out.push_back("unknown key " + key + " (line " + std::to_string(b.line) + ")");
  const auto fail = [&](const std::string& key, const std::string& what) {
    const auto it = bounds.find(key);
    out.push_back(key + " = " + (it == bounds.end() ? "?" : it->second.value) + ": " + what +
                  (it == bounds.end() ? "" : "  [reason: " + it->second.reason + "]"));
  };
  const auto number = [&](const std::string& key, double& v) {
    const auto it = bounds.find(key);
    if (it == bounds.end()) {
      fail(key, "missing");
      return false;
    }
    char* end = nullptr;
    v = std::strtod(it->second.value.c_str(), &end);
    if (it->second.value.empty() || *end != '\0' || !std::isfinite(v)) {
      fail(key, "not a finite number");
      return false;
    }
    return true;
  };
  const auto fmt = [](double v) {
    std::ostringstream o;
    o.precision(10);
    o << v;
    return o.str();
  };
  const auto at_least = [&](const std::string& key, double value, const std::string& what) {
    double b = 0.0;
    if (number(key, b) && !(value >= b)) fail(key, what + " " + fmt(value) + " is below it");
  };
  const auto at_most = [&](const std::string& key, double value, const std::string& what) {
    double b = 0.0;
    if (number(key, b) && !(value <= b)) fail(key, what + " " + fmt(value) + " is above it");
  };
  const auto exactly = [&](const std::string& key, double value, const std::string& what) {
    double b = 0.0;
    if (number(key, b) && value != b) fail(key, what + " is " + fmt(value));
  };

  if (const auto it = bounds.find("status"); it == bounds.end())
    fail("status", "missing");
  else if (it->second.value != f.status)
    fail("status", "the log's END_OF_LOG status is '" + f.status + "'");
  exactly("epochs", f.epochs, "the log's epoch count");
  at_least("final_icn_min", f.final_icn, "final ICN");
  at_most("final_icn_max", f.final_icn, "final ICN");

  // Per-epoch NEES: the fraction of the epochs (every UAV with truth) inside the band.
  double low = 0.0, high = 0.0, min_fraction = 0.0;
  if (number("nees_epoch_low", low) && number("nees_epoch_high", high) &&
      number("nees_epoch_min_fraction", min_fraction)) {
    int inside = 0;
    std::string outside;
    for (int k = 0; k < f.epochs; ++k) {
      const double v = f.epoch_average_nees[k];
      if (f.epoch_nees_samples[k] != f.uavs) {
        fail("nees_epoch_low", "epoch " + std::to_string(k) + " has " + std::to_string(f.epoch_nees_samples[k]) +
                                   " UAVs with truth; the band is stated for " + std::to_string(f.uavs));
      } else if (v >= low && v <= high) {
        ++inside;
      } else if (outside.size() < 200) {
        outside += " " + std::to_string(k) + ":" + fmt(v);
      }
    }
    const double fraction = f.epochs > 0 ? static_cast<double>(inside) / f.epochs : 0.0;
    if (!(fraction >= min_fraction))
      fail("nees_epoch_min_fraction", std::to_string(inside) + " of " + std::to_string(f.epochs) + " epochs inside [" +
                                          fmt(low) + ", " + fmt(high) + "]; outside (epoch:NEES):" + outside);
  }
  at_least("nees_mean_low", f.average_nees, "average NEES");
  at_most("nees_mean_high", f.average_nees, "average NEES");
  at_least("range_rmse_min_m", f.range_rmse_m, "line-of-sight RMSE over the beacon epochs");
  at_most("rmse_max_m", f.rmse_m, "3-D RMSE over the beacon epochs");
  exactly("beacons", f.beacons, "beacons consumed");
  at_least("fallback_fraction_min", f.fallback_fraction, "fallback fraction");
  at_most("fallback_fraction_max", f.fallback_fraction, "fallback fraction");
  return out;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += "\n  " + l;
  return s;
}

// ---------------------------------------------------------------------------------------------
// Missions and their variants.

std::string missions_root() {
  const char* env = std::getenv("LOSMIMO_GOLDEN_MISSIONS");
  return env && *env ? std::string(env) : source_path("datasets/missions");
}

struct MissionVariant {
  std::string mission;
  std::string variant;  // "ekf", "pf", "ekf+ceres"
};
void PrintTo(const MissionVariant& c, std::ostream* os) { *os << c.mission << " " << c.variant; }

std::vector<MissionVariant> mission_variants() {
  std::vector<MissionVariant> out;
  std::error_code ec;
  std::vector<std::filesystem::path> dirs;
  for (const auto& entry : std::filesystem::directory_iterator(missions_root(), ec))
    if (std::filesystem::exists(entry.path() / "invariants.ini")) dirs.push_back(entry.path());
  std::sort(dirs.begin(), dirs.end());
  for (const auto& dir : dirs)
    for (const std::string& v : listed_variants(read_invariants((dir / "invariants.ini").string())))
      out.push_back({dir.filename().string(), v});
  return out;
}

ReplayOptions options_of(const std::string& variant) {
  ReplayOptions o;
  o.estimator = localization::filter_kind_from_string(variant.substr(0, variant.find('+')));
  o.refine = variant.find("+ceres") != std::string::npos;
  return o;
}

class Missions : public ::testing::TestWithParam<MissionVariant> {};

TEST_P(Missions, InvariantsHoldOnAFreshReplay) {
  // GIVEN: a mission's rawlog and its invariants.
  const MissionVariant& c = GetParam();
  const std::string dir = missions_root() + "/" + c.mission;
  const InvariantsFile file = read_invariants(dir + "/invariants.ini");
  ASSERT_TRUE(file.problems.empty()) << joined(file.problems);
  const MissionLog log = load_log(dir + "/mission.rawlog");
  ASSERT_TRUE(log.complete) << log.stop_description();
  // WHEN: replayed with the variant's estimator.
  const ReplayFigures f = figures_of(log, replay_mission(log, options_of(c.variant)));
  std::cout << "[invariants] " << c.mission << " " << c.variant << ": status " << f.status << ", epochs " << f.epochs
            << ", final ICN " << f.final_icn << ", NEES " << f.average_nees << ", LoS RMSE " << f.range_rmse_m
            << " m, RMSE " << f.rmse_m << " m (beacon epochs), beacons " << f.beacons << ", fallback "
            << f.fallback_fraction << "\n";
  // THEN
  const std::vector<std::string> v = violations(bounds_of(file, c.variant), f);
  EXPECT_TRUE(v.empty()) << dir << "/invariants.ini [" << c.variant << "]:" << joined(v);
}

INSTANTIATE_TEST_SUITE_P(Golden, Missions, ::testing::ValuesIn(mission_variants()),
                         [](const ::testing::TestParamInfo<MissionVariant>& i) {
                           std::string v = i.param.variant;
                           for (char& ch : v)
                             if (ch == '+') ch = '_';
                           return i.param.mission + "_" + v;
                         });

// ---------------------------------------------------------------------------------------------
// The files: complete, every bound with its reason, and the numbers following from the config.

const std::vector<std::string>& shipped_missions() {
  static const std::vector<std::string> m = {"beacon_outage", "high_beacon_noise", "nominal"};
  return m;
}

TEST(GoldenInvariants, EveryShippedGoldenVariant_HasEveryInvariantWithAReason) {
  const std::string root = source_path("datasets/missions");
  std::set<std::string> on_disk;
  for (const auto& entry : std::filesystem::directory_iterator(root))
    if (entry.is_directory()) on_disk.insert(entry.path().filename().string());
  EXPECT_EQ(on_disk, std::set<std::string>(shipped_missions().begin(), shipped_missions().end()));
  for (const std::string& mission : shipped_missions()) {
    const InvariantsFile file = read_invariants(root + "/" + mission + "/invariants.ini");
    EXPECT_TRUE(file.problems.empty()) << joined(file.problems);
    // THEN: the listed variants are exactly golden/'s folders.
    std::set<std::string> golden;
    for (const auto& entry : std::filesystem::directory_iterator(root + "/" + mission + "/golden"))
      golden.insert(entry.path().filename().string());
    const std::vector<std::string> listed = listed_variants(file);
    EXPECT_EQ(std::set<std::string>(listed.begin(), listed.end()), golden) << mission;
    // AND: every variant has every key, and nothing else.
    for (const std::string& v : listed) {
      const Bounds b = bounds_of(file, v);
      for (const std::string& key : variant_keys()) EXPECT_TRUE(b.count(key)) << mission << " [" << v << "] " << key;
      EXPECT_EQ(b.size(), variant_keys().size()) << mission << " [" << v << "]";
    }
    for (const auto& [section, bounds] : file.sections)
      EXPECT_TRUE(section == "mission" || std::count(listed.begin(), listed.end(), section))
          << mission << " [" << section << "]";
  }
}

// The bounds recomputed from each mission's config (and the logged trajectory's ranges), never
// from a replay's output. A file value must be the theory's, rounded outward by at most kSlack.
TEST(GoldenInvariants, Bounds_FollowFromTheMissionsConfig) {
  constexpr double kSlack = 2e-3;  // relative: the files state 4 significant digits
  constexpr double kConfidence = 0.99;
  const auto expect_low = [&](const Bounds& b, const std::string& key, double theory, const std::string& where) {
    const double v = std::stod(b.at(key).value);
    EXPECT_LE(v, theory * (1.0 + 1e-12)) << where << key;
    EXPECT_GE(v, theory * (1.0 - kSlack)) << where << key;
  };
  const auto expect_high = [&](const Bounds& b, const std::string& key, double theory, const std::string& where) {
    const double v = std::stod(b.at(key).value);
    EXPECT_GE(v, theory * (1.0 - 1e-12)) << where << key;
    EXPECT_LE(v, theory * (1.0 + kSlack)) << where << key;
  };
  for (const std::string& mission : shipped_missions()) {
    const std::string dir = source_path("datasets/missions/" + mission);
    const InvariantsFile file = read_invariants(dir + "/invariants.ini");
    const MissionLog log = load_log(dir + "/mission.rawlog");
    ASSERT_TRUE(log.config) << mission;
    const MissionConfig& config = *log.config;
    const fusion::ClosedLoopConfig& cl = config.closed_loop;
    const localization::SimulatorConfig& truth = cl.simulator;
    // The theory below assumes a beacon every epoch outside the per-UAV outages, no outliers,
    // and the filter matched to the truth.
    ASSERT_EQ(truth.beacon_period_epochs, 1) << mission;
    ASSERT_TRUE(truth.outages.empty()) << mission;
    ASSERT_EQ(truth.outlier_fraction, 0.0) << mission;
    ASSERT_EQ(cl.filter.noise.sigma_range_m, truth.sigma_range_m) << mission;
    ASSERT_EQ(cl.filter.noise.sigma_angle_rad, truth.sigma_angle_rad) << mission;
    const int uavs = log.num_uavs;
    const int epochs = static_cast<int>(log.epochs.size());
    double range_max_m = 0.0;
    for (const auto& row : log.epochs)
      for (const LoggedUavEpoch& e : row)
        if (e.truth_m) range_max_m = std::max(range_max_m, e.truth_m->norm());
    // Beacons: every UAV-epoch outside the outage windows. Fallback: at least the outage
    // epochs from the degraded_after_epochs-th on (a UAV without a beacon at epoch 0 starts
    // from the degraded start-cube prior: all of them), at most every outage epoch.
    int beacons = uavs * epochs, outage_uav_epochs = 0, timed_out_uav_epochs = 0;
    for (const fusion::UavBeaconOutage& o : cl.outages) {
      const int first = std::min(o.window.first_epoch, epochs);
      const int end = std::min(o.window.first_epoch + o.window.num_epochs, epochs);
      outage_uav_epochs += end - first;
      const int degraded_from = first == 0 ? 0 : first + cl.filter.degraded_after_epochs - 1;
      timed_out_uav_epochs += std::max(0, end - degraded_from);
    }
    beacons -= outage_uav_epochs;
    const double uav_epochs = static_cast<double>(uavs) * epochs;
    // NEES: the average of `uavs` independent chi2(3) (one epoch; or every epoch, if each UAV's
    // NEES were fully correlated over epochs, the widest case) at kConfidence.
    const test_support::Chi2Band nees = test_support::chi2_average_band(3, uavs, kConfidence);
    // Line of sight: at best the steady-state Kalman variance of a random walk with the dead
    // reckoning's floor (q = floor^2) measured by the range (r = sigma_r^2) every epoch,
    // p = (-q + sqrt(q^2 + 4 q r)) / 2; times the lower 0.5% quantile of chi2(uavs) / uavs.
    const double q = truth.dr_sigma_floor_m * truth.dr_sigma_floor_m;
    const double r = truth.sigma_range_m * truth.sigma_range_m;
    const double p_los_m2 = 0.5 * (-q + std::sqrt(q * q + 4.0 * q * r));
    const double range_rmse_min_m =
        std::sqrt(p_los_m2 * test_support::chi2_quantile(uavs, 0.5 * (1.0 - kConfidence)) / uavs);
    // 3-D: at worst the beacon-only fix (range sigma along, range x angle sigma across, at the
    // largest logged range), times the upper 0.5% quantile of chi2(3 uavs) / (3 uavs).
    const double lateral_sigma_m = range_max_m * truth.sigma_angle_rad;
    const double beacon_only_rmse_m = std::sqrt(r + 2.0 * lateral_sigma_m * lateral_sigma_m);
    const double rmse_max_m =
        beacon_only_rmse_m *
        std::sqrt(test_support::chi2_quantile(3.0 * uavs, 0.5 * (1.0 + kConfidence)) / (3.0 * uavs));
    // Final ICN: converged runs reached the target; capped runs did not, but beat the start.
    const placement::Scenario& scenario = config.placement.scenario;
    const double start_icn =
        placement::evaluate_link(placement::ChannelModel(scenario).matrix(mission_start_positions_m(config)),
                                 scenario.noise_variance())
            .icn;
    const double target_icn = config.placement.run.target_icn;

    for (const std::string& v : listed_variants(file)) {
      const Bounds b = bounds_of(file, v);
      const std::string where = mission + " [" + v + "] ";
      EXPECT_EQ(b.at("status").value, log.run_end.status) << where;
      EXPECT_EQ(std::stoi(b.at("epochs").value), epochs) << where;
      if (log.run_end.status == "converged") {
        EXPECT_EQ(std::stod(b.at("final_icn_min").value), target_icn) << where;
        EXPECT_EQ(std::stod(b.at("final_icn_max").value), 1.0) << where;
      } else {
        EXPECT_EQ(epochs, config.placement.run.max_iterations) << where;
        expect_low(b, "final_icn_min", start_icn, where);
        EXPECT_EQ(std::stod(b.at("final_icn_max").value), target_icn) << where;
      }
      expect_low(b, "nees_epoch_low", nees.low, where);
      expect_high(b, "nees_epoch_high", nees.high, where);
      expect_low(b, "nees_mean_low", nees.low, where);
      expect_high(b, "nees_mean_high", nees.high, where);
      EXPECT_EQ(std::stod(b.at("nees_epoch_min_fraction").value), 0.9) << where;
      expect_low(b, "range_rmse_min_m", range_rmse_min_m, where);
      expect_high(b, "rmse_max_m", rmse_max_m, where);
      EXPECT_EQ(std::stoi(b.at("beacons").value), beacons) << where;
      if (outage_uav_epochs == 0) {
        EXPECT_EQ(std::stod(b.at("fallback_fraction_min").value), 0.0) << where;
        EXPECT_EQ(std::stod(b.at("fallback_fraction_max").value), 0.0) << where;
      } else {
        expect_low(b, "fallback_fraction_min", timed_out_uav_epochs / uav_epochs, where);
        expect_high(b, "fallback_fraction_max", outage_uav_epochs / uav_epochs, where);
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Negative controls: figures the checker must reject.

TEST(GoldenInvariants, DoctoredNees_IsAViolation) {
  // GIVEN: beacon_outage replayed with the EKF, its figures passing the [ekf+ceres] invariants
  // (the same bounds), and the same figures with the average NEES the golden once held.
  const std::string dir = source_path("datasets/missions/beacon_outage");
  const InvariantsFile file = read_invariants(dir + "/invariants.ini");
  const MissionLog log = load_log(dir + "/mission.rawlog");
  ReplayFigures f = figures_of(log, replay_mission(log, options_of("ekf")));
  const Bounds bounds = bounds_of(file, "ekf+ceres");
  f.average_nees = 2.78;
  EXPECT_TRUE(violations(bounds, f).empty()) << joined(violations(bounds, f));
  // WHEN: the summary says 1378.88.
  f.average_nees = 1378.88;
  const std::vector<std::string> v = violations(bounds, f);
  // THEN: exactly the NEES band's upper edge is violated, with its reason.
  ASSERT_EQ(v.size(), 1u) << joined(v);
  EXPECT_EQ(v[0].rfind("nees_mean_high", 0), 0u) << v[0];
  EXPECT_NE(v[0].find("reason: "), std::string::npos) << v[0];
  // AND: so is one epoch's NEES blown up by one UAV, and a wrong status.
  ReplayFigures g = figures_of(log, replay_mission(log, options_of("ekf")));
  g.status = "iteration_cap";
  for (int k = 0; k < g.epochs / 5; ++k) g.epoch_average_nees[k] += 1000.0 / g.uavs;
  const std::vector<std::string> w = violations(bounds, g);
  std::cout << "[invariants] beacon_outage doctored:" << joined(v) << joined(w) << "\n";
  EXPECT_EQ(w.size(), 2u) << joined(w);
}

TEST(GoldenInvariants, FilterToldHalfTheBeaconNoise_IsAViolation) {
  // GIVEN: the nominal mission replayed by an EKF (and refinement) that assumes half the true
  // beacon sigmas.
  const std::string dir = source_path("datasets/missions/nominal");
  const InvariantsFile file = read_invariants(dir + "/invariants.ini");
  MissionLog log = load_log(dir + "/mission.rawlog");
  ASSERT_TRUE(log.config);
  fusion::ClosedLoopConfig& cl = log.config->closed_loop;
  cl.filter.noise.sigma_range_m = cl.refinement.beacon_sigma_range_m = 0.5 * cl.simulator.sigma_range_m;
  cl.filter.noise.sigma_angle_rad = cl.refinement.beacon_sigma_angle_rad = 0.5 * cl.simulator.sigma_angle_rad;
  // WHEN
  const ReplayFigures f = figures_of(log, replay_mission(log, options_of("ekf")));
  const std::vector<std::string> v = violations(bounds_of(file, "ekf"), f);
  std::cout << "[invariants] nominal ekf told half the beacon noise:" << joined(v) << "\n";
  // THEN: the NEES invariants fail (overconfident beliefs), whatever else does.
  const auto names = [&](const std::string& key) {
    return std::any_of(v.begin(), v.end(), [&](const std::string& s) { return s.rfind(key, 0) == 0; });
  };
  EXPECT_TRUE(names("nees_mean_high")) << joined(v);
  EXPECT_TRUE(names("nees_epoch_min_fraction")) << joined(v);
}

TEST(GoldenInvariants, Reader_NamesAKeyWithoutReasonAndAnUnknownKey) {
  const std::string path = test_support::temp_path("invariants.ini");
  std::ofstream(path) << "[mission]\n# golden/ holds it\nvariants = ekf\n\n# a reason\nstatus = converged\nepochs = 3\n"
                         "[ekf]\n# typo\nbeacon = 3\n";
  const InvariantsFile f = read_invariants(path);
  ASSERT_EQ(f.problems.size(), 1u) << joined(f.problems);
  EXPECT_NE(f.problems[0].find(":7: epochs has no reason"), std::string::npos) << f.problems[0];
  const std::vector<std::string> v = violations(bounds_of(f, "ekf"), ReplayFigures{});
  EXPECT_TRUE(std::any_of(v.begin(), v.end(), [](const std::string& s) {
    return s.rfind("unknown key beacon", 0) == 0;
  })) << joined(v);
  EXPECT_TRUE(std::any_of(v.begin(), v.end(), [](const std::string& s) {
    return s.rfind("rmse_max_m = ?: missing", 0) == 0;
  })) << joined(v);
}

}  // namespace
}  // namespace losmimo::rawlog
