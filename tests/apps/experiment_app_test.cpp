#include <gtest/gtest.h>

#include "support/files.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <unistd.h>

#include "losmimo/apps/lib/experiment_app.h"
#include "in_process.h"
#include "losmimo/placement/experiment/channel_sweeps.h"
#include "losmimo/placement/experiment/engine.h"
#include "losmimo/placement/experiment/summary.h"
#include "losmimo/placement/capacity.h"
#include "losmimo/placement/metrics.h"

namespace lp = losmimo::placement;
namespace fs = std::filesystem;

namespace {
constexpr int kTrials = 2;
constexpr int kPointsPerSweep = 2;
constexpr int kAlgorithms = 5;

using losmimo::test_support::read_file;

std::vector<std::vector<std::string>> read_csv(const fs::path& p) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(read_file(p));
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::istringstream ls(line);
    std::string f;
    while (std::getline(ls, f, ',')) fields.push_back(f);
    rows.push_back(fields);
  }
  return rows;
}

// A tiny but complete run: every algorithm, both sweeps, two points, two trials.
losmimo::apps::ExperimentOptions tiny(const std::string& out, int threads) {
  losmimo::apps::ExperimentOptions o;
  o.out_dir = out;
  o.threads = threads;
  o.overrides = {"experiment.trials=" + std::to_string(kTrials), "experiment.sigma_loc_values_m=0, 0.1",
                 "experiment.sigma_act_values_m=0, 0.04", "experiment.plots=false", "placement.max_iterations=150"};
  return o;
}

class ExperimentApp : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // One folder per process: ctest runs each test in its own process, in parallel.
    const std::string pid = std::to_string(::getpid());
    dir1_ = fs::path(::testing::TempDir()) / ("losmimo_exp_t1_" + pid);
    dir2_ = fs::path(::testing::TempDir()) / ("losmimo_exp_t2_" + pid);
    fs::remove_all(dir1_);
    fs::remove_all(dir2_);
    ASSERT_EQ(losmimo::test_support::run_experiment(tiny(dir1_.string(), 1)), 0);
    ASSERT_EQ(losmimo::test_support::run_experiment(tiny(dir2_.string(), 2)), 0);
  }
  static fs::path dir1_, dir2_;
};
fs::path ExperimentApp::dir1_;
fs::path ExperimentApp::dir2_;
}  // namespace

TEST_F(ExperimentApp, TinyConfig_WritesEveryOutputWithTheDocumentedColumns) {
  for (const char* f : {"trials.csv", "positions.csv", "traces.csv", "summary.csv", "config.ini", "report.md",
                        "fig1a.gp", "fig2a.gp", "fig2b.gp", "fig3.gp", "fig2a.dat"}) {
    EXPECT_TRUE(fs::exists(dir1_ / f)) << f;
  }
  EXPECT_FALSE(fs::exists(dir1_ / "trials.csv.partial"));
  const auto trials = read_csv(dir1_ / "trials.csv");
  const std::string header = read_file(dir1_ / "trials.csv").substr(0, read_file(dir1_ / "trials.csv").find('\n'));
  EXPECT_EQ(header.rfind("sweep,value,algorithm,trial,seed,iterations,converged,final_icn,dist_to_icn050_m,"
                         "dist_to_icn095_m,dist_total_m,probe_dist_m,sinr_nv_db,sinr_zf_db,sinr_mf_db,"
                         "sum_rate_nv_bps_hz,sum_rate_zf_bps_hz",
                         0),
            0u);
  ASSERT_EQ(trials.size(), 1u + 2 * kPointsPerSweep * kAlgorithms * kTrials);
  const auto positions = read_csv(dir1_ / "positions.csv");
  EXPECT_EQ(positions.size(), 1u + (trials.size() - 1) * 16 * 2);
  const auto summary = read_csv(dir1_ / "summary.csv");
  EXPECT_EQ(summary.size(), 1u + 2 * kPointsPerSweep * kAlgorithms);
}

TEST_F(ExperimentApp, SeedsAreDerivedAndStartsAreShared) {
  const auto rows = read_csv(dir1_ / "trials.csv");
  const losmimo::experiment::ExperimentSettings settings;  // the tiny run keeps the default seed
  std::map<std::string, std::string> start_seed_of_trial;
  std::map<std::string, std::string> seed_of_point_trial;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const auto& r = rows[i];
    const int point = std::stod(r[1]) == 0.0 ? 0 : 1;
    const int trial = std::stoi(r[3]);
    EXPECT_EQ(r[4], std::to_string(losmimo::experiment::trial_seed(settings, r[0], point, trial)));
    EXPECT_EQ(r[21], std::to_string(losmimo::experiment::trial_start_seed(settings, trial)));
    // Common random numbers: one start seed per trial for every sweep, point and algorithm,
    // and one error seed per (sweep, point, trial) for every algorithm.
    auto [it, inserted] = start_seed_of_trial.emplace(r[3], r[21]);
    EXPECT_EQ(it->second, r[21]);
    auto [jt, fresh] = seed_of_point_trial.emplace(r[0] + r[1] + "," + r[3], r[4]);
    EXPECT_EQ(jt->second, r[4]);
    EXPECT_TRUE(r[6] == "0" || r[6] == "1");
  }
  EXPECT_EQ(start_seed_of_trial.size(), static_cast<std::size_t>(kTrials));
  EXPECT_EQ(seed_of_point_trial.size(), static_cast<std::size_t>(2 * kPointsPerSweep * kTrials));
}

TEST_F(ExperimentApp, OneAndTwoThreads_GiveByteIdenticalResults) {
  for (const char* f : {"trials.csv", "positions.csv", "summary.csv", "traces.csv"}) {
    ASSERT_GT(read_file(dir1_ / f).size(), 100u) << f;
    EXPECT_EQ(read_file(dir1_ / f), read_file(dir2_ / f)) << f;
  }
}

TEST_F(ExperimentApp, MetricsRecomputedFromPositions_AgreeWithTrials) {
  const auto trials = read_csv(dir1_ / "trials.csv");
  const auto positions = read_csv(dir1_ / "positions.csv");
  std::map<std::string, Eigen::Matrix3Xd> final_of;
  for (std::size_t i = 1; i < positions.size(); ++i) {
    const auto& p = positions[i];
    if (p[5] != "final") continue;
    const std::string key = p[0] + "," + p[1] + "," + p[2] + "," + p[3];
    Eigen::Matrix3Xd& q = final_of[key];
    if (q.cols() == 0) q.resize(3, 16);
    q.col(std::stoi(p[4]) - 1) << std::stod(p[6]), std::stod(p[7]), std::stod(p[8]);
  }
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  for (std::size_t i = 1; i < trials.size(); ++i) {
    const auto& t = trials[i];
    const Eigen::Matrix3Xd& q = final_of.at(t[0] + "," + t[1] + "," + t[2] + "," + t[3]);
    const lp::LinkMetrics m = lp::evaluate_link(model.matrix(q), s.noise_variance());
    EXPECT_NEAR(std::stod(t[7]), m.icn, 1e-8) << i;
    EXPECT_NEAR(std::stod(t[12]), lp::to_db(m.sinr.nv(0)), 1e-6) << i;
    EXPECT_NEAR(std::stod(t[15]), m.sum_rate_nv_bps_hz, 1e-6) << i;
  }
}

TEST(ExperimentConfig, BadValues_StopBeforeAnyWorkNamingTheKey) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"experiment.trails=3", "trails"},
      {"experiment.trials=-1", "trials"},
      {"errors.sigma_loc_m=nan", "sigma_loc_m"},
      {"experiment.sigma_loc_values_m=0, nan", "sigma_loc_values_m"},
      {"gd.step=0", "step"},
      {"bf.step=-0.3", "step"},
      {"experiment.algorithms=gd, sa", "algorithms"},
      {"experiment.sweeps=sigma_loc_m, beacon", "sweeps"},
  };
  for (const auto& [override_text, key] : cases) {
    losmimo::apps::ExperimentOptions o;
    o.out_dir = (fs::path(::testing::TempDir()) / ("losmimo_exp_bad_" + std::to_string(::getpid()))).string();
    fs::remove_all(*o.out_dir);
    o.overrides = {override_text};
    std::string err;
    EXPECT_EQ(losmimo::test_support::run_experiment(o, &err), 2) << override_text;
    EXPECT_NE(err.find(key), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(*o.out_dir)) << "work started for " << override_text;
    EXPECT_FALSE(fs::exists(*o.out_dir + ".partial")) << "work started for " << override_text;
  }
}

TEST(ExperimentAlgorithms, UraLatticeExact_IsSelectableAndConvergesWithoutErrors) {
  // GIVEN: only the exact lattice, no errors (sigma 0), two trials
  const fs::path dir = fs::path(::testing::TempDir()) / ("losmimo_exp_exact_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  losmimo::apps::ExperimentOptions o;
  o.out_dir = dir.string();
  o.threads = 1;
  o.overrides = {"experiment.trials=2",
                 "experiment.sweeps=sigma_loc_m",
                 "experiment.sigma_loc_values_m=0",
                 "experiment.algorithms=ura_lattice_exact",
                 "experiment.plots=false",
                 "experiment.fig1_trials=0"};
  ASSERT_EQ(losmimo::test_support::run_experiment(o), 0);
  const auto rows = read_csv(dir / "trials.csv");
  ASSERT_EQ(rows.size(), 3u);
  for (std::size_t i = 1; i < rows.size(); ++i) {
    // THEN: it is named in trials.csv and reaches ICN 0.95 in its first iteration, as ura does
    EXPECT_EQ(rows[i][2], "ura_lattice_exact");
    EXPECT_EQ(rows[i][5], "1") << "iterations";
    EXPECT_EQ(rows[i][6], "1") << "converged";
    EXPECT_GE(std::stod(rows[i][7]), 0.95) << "final_icn";
  }
  fs::remove_all(dir);
}

TEST(ExperimentAlgorithms, Cap_RunsInTheSweepsAndReachesTheOrthogonalBound) {
  // GIVEN: only the capacity planner, no errors, two trials, on the paper's BS (Nr = Nt = 16) and
  // on an 8 x 8 BS (bs_antennas 64: Nr < Nt)
  const fs::path dir = fs::path(::testing::TempDir()) / ("losmimo_exp_cap_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  losmimo::apps::ExperimentOptions o;
  o.out_dir = dir.string();
  o.threads = 1;
  o.overrides = {"experiment.trials=2",
                 "experiment.sweeps=sigma_loc_m, bs_antennas",
                 "experiment.sigma_loc_values_m=0",
                 "experiment.bs_antennas_values=64",
                 "experiment.algorithms=cap",
                 "experiment.plots=false",
                 "experiment.fig1_trials=0"};
  std::ostringstream out, err;
  ASSERT_EQ(losmimo::apps::run_experiment_app(o, losmimo::experiment::channel_sweep_extensions(), out, err), 0)
      << err.str();
  const auto rows = read_csv(dir / "trials.csv");
  ASSERT_EQ(rows.size(), 5u);
  const auto column = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(rows[0].begin(), rows[0].end(), name) - rows[0].begin());
  };
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const int nt = rows[i][column("sweep")] == "bs_antennas" ? 64 : 16;
    const double bound =
        losmimo::placement::orthogonal_capacity_bps_hz(16, nt, 0.1, losmimo::placement::CapPower::kEqual);
    // THEN: named in trials.csv, converged, and its sum rate within 1 % of the bound
    EXPECT_EQ(rows[i][column("algorithm")], "cap");
    EXPECT_EQ(rows[i][column("converged")], "1");
    EXPECT_GT(std::stod(rows[i][column("sum_rate_zf_bps_hz")]) / bound, 0.99) << "row " << i;
  }
  fs::remove_all(dir);
}
