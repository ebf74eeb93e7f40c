// The apps' options and messages: an option given empty is refused, not taken as "not given";
// --resume stays in its own folder; errors name the option that set a value; [experiment] keys
// are checked by every app that accepts them; a huge value is not echoed whole; a UTF-8
// byte-order mark is accepted at the start of a file and shown, not hidden, elsewhere.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "losmimo/apps/lib/eval_app.h"
#include "losmimo/apps/lib/experiment_app.h"
#include "in_process.h"

namespace losmimo::apps {
namespace {

namespace fs = std::filesystem;

fs::path temp(const std::string& name) {
  return fs::path(::testing::TempDir()) / ("losmimo_msg_" + std::to_string(::getpid()) + "_" + name);
}

int eval(const EvalOptions& o, std::string* err_text) {
  std::ostringstream out, err;
  const int code = run_eval_app(o, out, err);
  *err_text = err.str();
  return code;
}

std::string positions_file() { return std::string(LOSMIMO_SOURCE_DIR) + "/datasets/examples/ura_optimal_16.csv"; }

TEST(AppOptions, EmptyShardOutOrResume_AreRefusedBeforeAnyWork) {
  std::string err;
  ExperimentOptions o;
  o.out_dir = temp("x").string();
  o.shard = "";
  EXPECT_EQ(test_support::run_experiment(o, &err), 2);
  EXPECT_NE(err.find("--shard ''"), std::string::npos) << err;
  o.shard.reset();
  o.out_dir = "";
  EXPECT_EQ(test_support::run_experiment(o, &err), 2);
  EXPECT_NE(err.find("--out ''"), std::string::npos) << err;
  o.out_dir.reset();
  o.resume_dir = "";
  EXPECT_EQ(test_support::run_experiment(o, &err), 2);
  EXPECT_NE(err.find("--resume ''"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(temp("x")));
}

TEST(AppOptions, ResumeWithAnotherOut_IsRefused) {
  std::string err;
  ExperimentOptions o;
  o.resume_dir = temp("run").string();
  o.out_dir = temp("other").string();
  EXPECT_EQ(test_support::run_experiment(o, &err), 2);
  EXPECT_NE(err.find("finishes the run in " + temp("run").string() + " itself"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(temp("other")));
}

TEST(AppOptions, TrialsOrThreadsOutOfRange_NameTheOptionNotSet) {
  std::string err;
  ExperimentOptions o;
  o.out_dir = temp("t").string();
  o.trials = 2'000'000;
  EXPECT_EQ(test_support::run_experiment(o, &err), 2);
  EXPECT_NE(err.find("--trials: [experiment] trials: 2000000 is out of range"), std::string::npos) << err;
  EXPECT_EQ(err.find("--set"), std::string::npos) << err;
  o.trials = 0;
  o.threads = 5000;
  EXPECT_EQ(test_support::run_experiment(o, &err), 2);
  EXPECT_NE(err.find("--threads: [experiment] threads"), std::string::npos) << err;
}

TEST(AppOptions, EvalWithABadExperimentKey_Exits2NamingIt) {
  std::string err;
  EvalOptions o;
  o.positions_path = positions_file();
  o.overrides = {"experiment.algorithms=not_an_algorithm"};
  EXPECT_EQ(eval(o, &err), 2);
  EXPECT_NE(err.find("algorithm"), std::string::npos) << err;
  EXPECT_NE(err.find("not_an_algorithm"), std::string::npos) << err;
}

TEST(AppMessages, HugeValue_IsShortenedNotEchoedWhole) {
  std::string err;
  EvalOptions o;
  o.positions_path = positions_file();
  o.overrides = {"scenario.snr_db=" + std::string(1'000'000, '7') + "x"};
  EXPECT_EQ(eval(o, &err), 2);
  EXPECT_LT(err.size(), 1000u) << err.substr(0, 1000);
  EXPECT_NE(err.find("... (1000001 bytes)' is not a finite number"), std::string::npos) << err;
}

TEST(AppMessages, ByteOrderMark_AcceptedAtTheStartOfAFileAndShownElsewhere) {
  const std::string bom = "\xEF\xBB\xBF";
  const fs::path config = temp("bom.ini"), positions = temp("bom.csv");
  std::ofstream(config, std::ios::binary) << bom << "[scenario]\nsnr_db = 10\n";
  std::ofstream(positions, std::ios::binary) << bom << "x,y,z\n1000,0,0\n1000,1,0\n";
  std::string err;
  EvalOptions o;
  o.positions_path = positions.string();
  o.config_path = config.string();
  EXPECT_EQ(eval(o, &err), 0) << err;
  o.overrides = {"scenario.snr_db=" + bom + "10"};
  EXPECT_EQ(eval(o, &err), 2);
  EXPECT_NE(err.find("'\\xEF\\xBB\\xBF10' is not a finite number"), std::string::npos) << err;
  fs::remove(config);
  fs::remove(positions);
}

// Used to pool both points' trials into one point (one summary row with twice the trials).
TEST(AppSettings, SweepValueListedTwice_IsRefused) {
  std::string err;
  ExperimentOptions o;
  o.out_dir = temp("dup").string();
  o.overrides = {"experiment.sigma_loc_values_m=0, 0"};
  EXPECT_EQ(test_support::run_experiment(o, &err), 2);
  EXPECT_NE(err.find("[experiment] sigma_loc_values_m: '0' listed twice"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(temp("dup.partial")));
}

// Used to run, and report "iterations to ICN 0.95: 0.00".
TEST(AppSettings, ZeroIterations_IsRefused) {
  std::string err;
  ExperimentOptions o;
  o.out_dir = temp("zero").string();
  o.overrides = {"placement.max_iterations=0"};
  EXPECT_EQ(test_support::run_experiment(o, &err), 2);
  EXPECT_NE(err.find("[placement] max_iterations: 0 is out of range [1, "), std::string::npos) << err;
}

// Used to say "ura needs ..." when only ura_lattice was listed.
TEST(AppSettings, UraLatticeOnAnotherSwarm_NamesUraLattice) {
  std::string err;
  ExperimentOptions o;
  o.out_dir = temp("lattice").string();
  o.overrides = {"scenario.num_uavs=20", "experiment.algorithms=gd, ura_lattice"};
  EXPECT_EQ(test_support::run_experiment(o, &err), 2);
  EXPECT_NE(err.find("ura_lattice needs scenario.num_uavs <= bs_rows * bs_cols (16), got 20"), std::string::npos)
      << err;
}

}  // namespace
}  // namespace losmimo::apps
