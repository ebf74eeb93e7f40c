// The co-evaluation sweeps (coevaluation.h) end to end through losmimo-experiment's entry point,
// run_experiment_app, with fusion's extensions. Seeded, never retried.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <unistd.h>

#include "losmimo/apps/lib/experiment_app.h"
#include "losmimo/fusion/coevaluation/coevaluation.h"
#include "losmimo/fusion/coevaluation/extensions.h"
#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/experiment/engine.h"
#include "losmimo/placement/experiment/summary.h"

namespace losmimo::coevaluation {
namespace {

namespace fs = std::filesystem;
namespace lp = placement;

constexpr int kTrials = 2;
constexpr double kLargestNoise_m = 0.18;
const std::vector<std::string> kBeaconAlgorithms = {
    "gd_gauss", "gd_ekf",  "gd_gauss_matched", "gd_gauss_shape_matched", "gd_pf", "gd_ekf_ceres",
    "bf",       "ura_ekf", "centralized"};
const std::vector<std::string> kOutageAlgorithms = {"gd_ekf", "gd_ekf_nofallback"};
const std::vector<int> kOutageValues = {0, 4};

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// trials.csv as one map per row, column name -> text.
std::vector<std::map<std::string, std::string>> read_rows(const fs::path& p, std::vector<std::string>* header) {
  std::istringstream in(read_file(p));
  std::string line;
  const auto split = [](const std::string& l) {
    std::vector<std::string> fields;
    std::istringstream ls(l);
    std::string f;
    while (std::getline(ls, f, ',')) fields.push_back(f);
    return fields;
  };
  std::getline(in, line);
  *header = split(line);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    const std::vector<std::string> fields = split(line);
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header->size() && i < fields.size(); ++i) row[(*header)[i]] = fields[i];
    rows.push_back(row);
  }
  return rows;
}

double number(const std::map<std::string, std::string>& row, const std::string& column) {
  return std::stod(row.at(column));  // "nan" parses as NaN
}

// A tiny run of both co-evaluation sweeps: every algorithm, two points each, two trials.
losmimo::apps::ExperimentOptions tiny(const std::string& out, int threads) {
  losmimo::apps::ExperimentOptions o;
  o.out_dir = out;
  o.threads = threads;
  o.overrides = {"experiment.sweeps=beacon_noise_m, beacon_outage",
                 "experiment.trials=" + std::to_string(kTrials),
                 "experiment.plots=false",
                 "placement.max_iterations=150",
                 "coevaluation.beacon_noise_values_m=0, 0.18",
                 "closed_loop.num_particles=200",
                 "coevaluation.outage_values=0, 4"};
  return o;
}

int run_app(const losmimo::apps::ExperimentOptions& o, std::string* err_text = nullptr) {
  std::ostringstream out, err;
  const int code = losmimo::apps::run_experiment_app(o, experiment_extensions(), out, err);
  if (err_text) *err_text = err.str();
  return code;
}

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("losmimo_coeval_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

losmimo::experiment::ExperimentSettings settings_from(const std::vector<std::string>& overrides) {
  losmimo::common::IniConfig config;
  for (const std::string& o : overrides) config.set_override(o);
  return losmimo::experiment::load_experiment_settings(config, experiment_extensions());
}

// A matched Gaussian row: its Gaussian has gd_ekf's measured `matched` error (loc_lateral_rmse_m,
// shape_lateral_rmse_m) of the same trial and point, and its paired differences are gd_ekf's
// columns minus its own.
void expect_matched_row(const std::map<std::string, std::string>& r,
                        const std::vector<std::map<std::string, std::string>>& rows, const std::string& matched) {
  // THEN (the matched error): its Gaussian has gd_ekf's measured lateral RMSE of the same
  // trial and point.
  const auto ekf = std::find_if(rows.begin(), rows.end(), [&](const auto& o) {
    return o.at("sweep") == r.at("sweep") && o.at("value") == r.at("value") && o.at("trial") == r.at("trial") &&
           o.at("algorithm") == "gd_ekf";
  });
  ASSERT_NE(ekf, rows.end());
  const double ekf_error_m = number(*ekf, matched);
  EXPECT_GT(ekf_error_m, 0.0);
  EXPECT_NEAR(number(r, matched), ekf_error_m, 1e-9 * ekf_error_m + 1e-12);
  EXPECT_TRUE(std::isnan(number(r, "nees")));
  // THEN: the paired differences are gd_ekf's columns minus its own, from the CSV.
  const double travel_m = number(*ekf, "dist_to_icn095_m") - number(r, "dist_to_icn095_m");
  if (std::isnan(travel_m)) {
    EXPECT_TRUE(std::isnan(number(r, "paired_travel_diff_m")));
  } else {
    EXPECT_NEAR(number(r, "paired_travel_diff_m"), travel_m, 1e-8);
  }
  EXPECT_EQ(number(r, "paired_iterations_diff"), number(*ekf, "iterations") - number(r, "iterations"));
}

// One test, so that ctest's process per test runs the two apps once.
TEST(CoevaluationApp, TinyConfig_EveryAlgorithmAndColumn_SameBytesInOneAndTwoThreads) {
  // GIVEN / WHEN: the same tiny configuration with 1 and 2 threads.
  const fs::path dir1 = temp_dir("t1"), dir2 = temp_dir("t2");
  std::string err;
  ASSERT_EQ(run_app(tiny(dir1.string(), 1), &err), 0) << err;
  ASSERT_EQ(run_app(tiny(dir2.string(), 2), &err), 0) << err;

  // THEN: results do not depend on the thread count.
  for (const char* f : {"trials.csv", "positions.csv", "summary.csv"}) {
    EXPECT_EQ(read_file(dir1 / f), read_file(dir2 / f)) << f;
  }
  for (const char* f :
       {"coeval_sinr.gp", "coeval_sinr.dat", "coeval_travel.gp", "coeval_rmse.gp", "outage.gp", "outage.dat"}) {
    EXPECT_TRUE(fs::exists(dir1 / f)) << f;
  }
  const std::string report = read_file(dir1 / "report.md");
  EXPECT_NE(report.find("## Co-evaluation: beacon noise"), std::string::npos);
  EXPECT_NE(report.find("**Target**"), std::string::npos);
  EXPECT_NE(report.find("### Integrating the estimator at matched error"), std::string::npos);
  EXPECT_NE(report.find("## Co-evaluation: beacon outage"), std::string::npos);

  // THEN: the extra columns, and one row per (sweep, point, algorithm, trial).
  std::vector<std::string> header;
  const auto rows = read_rows(dir1 / "trials.csv", &header);
  for (const losmimo::experiment::ExtensionMetric& c : coevaluation_metrics()) {
    EXPECT_NE(std::find(header.begin(), header.end(), c.name), header.end()) << c.name;
  }
  std::map<std::string, int> count;
  for (const auto& r : rows) ++count[r.at("sweep") + "/" + r.at("algorithm")];
  for (const std::string& a : kBeaconAlgorithms) EXPECT_EQ(count["beacon_noise_m/" + a], 2 * kTrials) << a;
  for (const std::string& a : kOutageAlgorithms) EXPECT_EQ(count["beacon_outage/" + a], 2 * kTrials) << a;
  EXPECT_EQ(rows.size(), (kBeaconAlgorithms.size() + kOutageAlgorithms.size()) * 2 * kTrials);

  for (const auto& r : rows) {
    const std::string a = r.at("algorithm");
    const double value = number(r, "value");
    if (r.at("sweep") != "beacon_noise_m") continue;
    if (a == "centralized") {
      // THEN: the bound is feasible and flown in one go.
      EXPECT_EQ(r.at("iterations"), "0");
      EXPECT_GE(number(r, "final_icn"), 0.95 - 1e-9);
      EXPECT_NEAR(number(r, "dist_to_icn095_m"), number(r, "dist_total_m"), 0.01 * number(r, "dist_total_m"));
      EXPECT_TRUE(std::isnan(number(r, "loc_rmse_m")));
    }
    if (a == "bf" || a == "centralized") {
      EXPECT_TRUE(std::isnan(number(r, "nees"))) << a;
      continue;
    }
    if (a == "gd_gauss") {
      EXPECT_NEAR(number(r, "loc_lateral_rmse_m"), std::sqrt(2.0) * value, 1e-9);  // CSV: 10 digits
      continue;
    }
    if (a == "gd_gauss_matched" || a == "gd_gauss_shape_matched") {
      expect_matched_row(r, rows, a == "gd_gauss_matched" ? "loc_lateral_rmse_m" : "shape_lateral_rmse_m");
      continue;
    }
    EXPECT_TRUE(std::isnan(number(r, "paired_travel_diff_m"))) << a;
    EXPECT_TRUE(std::isnan(number(r, "paired_iterations_diff"))) << a;
    if (value != kLargestNoise_m) continue;
    // THEN (the matching): the beacon-only lateral RMSE is sqrt(2) x the swept per-axis value,
    // and every estimator beats it.
    EXPECT_NEAR(number(r, "beacon_lateral_rmse_m"), std::sqrt(2.0) * value, 0.05 * std::sqrt(2.0) * value) << a;
    EXPECT_GT(number(r, "loc_lateral_rmse_m"), 0.0) << a;
    EXPECT_LT(number(r, "loc_lateral_rmse_m"), number(r, "beacon_lateral_rmse_m")) << a;
    EXPECT_GT(number(r, "nees"), 1.5) << a;
    EXPECT_LT(number(r, "nees"), 6.0) << a;
    if (a != "ura_ekf") {
      EXPECT_EQ(number(r, "bf_fallback_fraction"), 0.0) << a;
    }
  }
}

TEST(CoevaluationApp, BadCoevaluationKeyOrValue_Exit2NamingTheKeyBeforeAnyWork) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"coevaluation.bogus=1", {"bogus"}},
      {"coevaluation.algorithms=gd_ekf, gd_magic", {"[coevaluation] algorithms", "gd_magic"}},
      {"coevaluation.algorithms=gd_ekf, gd_ekf", {"[coevaluation] algorithms", "twice"}},
      {"coevaluation.outage_algorithms=bf", {"[coevaluation] outage_algorithms", "bf"}},
      {"coevaluation.beacon_noise_values_m=0, -0.1", {"[coevaluation] beacon_noise_values_m", "-0.1"}},
      {"coevaluation.beacon_noise_values_m=0, abc", {"[coevaluation] beacon_noise_values_m", "abc"}},
      {"closed_loop.beacon_sigma_range_m=-1", {"[closed_loop] beacon_sigma_range_m", "-1"}},
      {"closed_loop.dr_sigma_floor_m=0", {"[closed_loop] dr_sigma_floor_m", "0"}},
      {"closed_loop.num_particles=0", {"[closed_loop] num_particles", "0"}},
      {"closed_loop.window_epochs=0", {"[closed_loop] window_epochs", "0"}},
      {"closed_loop.filter=pf", {"[closed_loop] filter", "unknown key"}},  // set per algorithm
      // The old spellings of the shared [closed_loop] settings name the key to use.
      {"coevaluation.sigma_range_m=0.1", {"[coevaluation] sigma_range_m", "[closed_loop] beacon_sigma_range_m"}},
      {"coevaluation.pf_particles=200", {"[coevaluation] pf_particles", "[closed_loop] num_particles"}},
      {"coevaluation.refine_window_epochs=5", {"[coevaluation] refine_window_epochs", "[closed_loop] window_epochs"}},
      {"coevaluation.refine_use_csi=true", {"[coevaluation] refine_use_csi", "[closed_loop] use_csi"}},
      {"coevaluation.ura_variant=hexagonal", {"[coevaluation] ura_variant", "hexagonal"}},
      {"coevaluation.outage_values=0, 17", {"[coevaluation] outage_values", "17"}},
      {"coevaluation.outage_degraded_after_epochs=0", {"[coevaluation] outage_degraded_after_epochs", "0"}},
  };
  for (const auto& [assignment, expected] : cases) {
    const fs::path dir = temp_dir("bad");
    losmimo::apps::ExperimentOptions o = tiny(dir.string(), 1);
    o.overrides.push_back(assignment);
    std::string err;
    // WHEN
    const int code = run_app(o, &err);
    // THEN
    EXPECT_EQ(code, 2) << assignment;
    for (const std::string& e : expected) EXPECT_NE(err.find(e), std::string::npos) << assignment << ": " << err;
    EXPECT_FALSE(fs::exists(dir)) << assignment << ": work started";
  }
  // ura_ekf needs a square swarm: with 9 UAVs the configuration is refused, naming the key.
  const fs::path dir = temp_dir("bad");
  losmimo::apps::ExperimentOptions o = tiny(dir.string(), 1);
  o.overrides.push_back("scenario.num_uavs=9");
  std::string err;
  EXPECT_EQ(run_app(o, &err), 2);
  EXPECT_NE(err.find("[coevaluation] algorithms"), std::string::npos) << err;
  EXPECT_NE(err.find("ura_ekf"), std::string::npos) << err;
}

TEST(CoevaluationOutage, EightUavsLoseTheBeaconMidMission_TheyFallBackAndTheSwarmConverges) {
  // GIVEN: half the swarm loses the beacon for epochs 10..39 (the default window).
  constexpr int kStarts = 3;
  const losmimo::experiment::ExperimentSettings s =
      settings_from({"experiment.sweeps=beacon_outage", "experiment.trials=3", "coevaluation.outage_values=0, 8",
                     "coevaluation.outage_algorithms=gd_ekf"});
  ASSERT_EQ(outage_uavs(8, 16), (std::vector<int>{0, 2, 4, 6, 8, 10, 12, 14}));
  int observed = 0;  // runs long enough for the fallback to show
  for (int trial = 0; trial < kStarts; ++trial) {
    // WHEN
    const std::vector<losmimo::experiment::TrialRecord> none = run_outage_trial(s, 0, trial);
    const std::vector<losmimo::experiment::TrialRecord> lost = run_outage_trial(s, 1, trial);
    ASSERT_EQ(none.size(), 1u);
    ASSERT_EQ(lost.size(), 1u);
    // THEN: nobody falls back without an outage; with it the lost UAVs do (if the run lasts
    // past the degradation, epoch 15), and the swarm still reaches the target.
    EXPECT_TRUE(none[0].converged) << "trial " << trial;
    EXPECT_EQ(none[0].extension.at(kBfFallbackFraction), 0.0);
    EXPECT_TRUE(lost[0].converged) << "trial " << trial;
    if (lost[0].iterations > 16) {
      ++observed;
      EXPECT_GT(lost[0].extension.at(kBfFallbackFraction), 0.0) << "trial " << trial;
      EXPECT_GT(lost[0].probe_dist_m, 0.0) << "trial " << trial;  // BF probe flights
    }
    EXPECT_LE(lost[0].extension.at(kBfFallbackFraction), 0.5);  // only 8 of 16 UAVs can fall back
  }
  EXPECT_GE(observed, 2);
}

TEST(CoevaluationPairing, GdGaussAtBeaconNoiseZero_EqualsBuiltInGdAtSigmaLocZero) {
  // GIVEN: both sweeps in one configuration, no actuation error (so no seed enters).
  const losmimo::experiment::ExperimentSettings s = settings_from(
      {"experiment.sweeps=sigma_loc_m, beacon_noise_m", "experiment.sigma_loc_values_m=0", "experiment.algorithms=gd",
       "coevaluation.beacon_noise_values_m=0", "coevaluation.algorithms=gd_gauss", "placement.max_iterations=300"});
  const auto same = [](const losmimo::experiment::TrialRecord& a, const losmimo::experiment::TrialRecord& b) {
    return a.iterations == b.iterations && a.final_m.cols() == b.final_m.cols() &&
           std::memcmp(a.final_m.data(), b.final_m.data(), sizeof(double) * a.final_m.size()) == 0 &&
           a.dist_total_m == b.dist_total_m;
  };
  for (int trial = 0; trial < 2; ++trial) {
    // WHEN
    const std::vector<losmimo::experiment::TrialRecord> builtin =
        losmimo::experiment::run_trial(s, losmimo::experiment::kSweepSigmaLoc, 0, trial);
    const std::vector<losmimo::experiment::TrialRecord> coeval = run_beacon_noise_trial(s, 0, trial);
    ASSERT_EQ(builtin.size(), 1u);
    ASSERT_EQ(coeval.size(), 1u);
    // THEN: same start, same run, bit for bit.
    EXPECT_EQ(coeval[0].start_seed, builtin[0].start_seed);
    EXPECT_TRUE(same(coeval[0], builtin[0])) << "trial " << trial;
  }
  // THEN (the check can fail): another trial's start gives another run.
  EXPECT_FALSE(same(run_beacon_noise_trial(s, 0, 1)[0],
                    losmimo::experiment::run_trial(s, losmimo::experiment::kSweepSigmaLoc, 0, 0)[0]));
}

}  // namespace
}  // namespace losmimo::coevaluation
