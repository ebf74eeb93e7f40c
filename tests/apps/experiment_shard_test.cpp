// --shard i/N and `merge`: the merged shards are byte-identical to one process; bad shard
// specs, shards of another config and missing or repeated shards stop with exit code 2; shards
// that ran the kernels on different instruction sets merge with a note.
// (Interrupted shards and damaged records: experiment_interrupt_test.cpp, records_proof_test.cpp.)
#include <gtest/gtest.h>

#include "support/files.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "losmimo/apps/lib/experiment_app.h"
#include "in_process.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/experiment/engine.h"
#include "losmimo/placement/experiment/records.h"
#include "losmimo/placement/experiment/shards.h"
#include "losmimo/placement/experiment/summary.h"
#include "losmimo/placement/isa.h"

namespace lp = losmimo::placement;
namespace fs = std::filesystem;

namespace {
constexpr int kShards = 3;

using losmimo::test_support::read_file;

// Small but complete: every algorithm, both sweeps, 3 trials (9 jobs over 3 shards).
losmimo::apps::ExperimentOptions tiny(const fs::path& out, int threads) {
  losmimo::apps::ExperimentOptions o;
  o.out_dir = out.string();
  o.threads = threads;
  o.overrides = {"experiment.trials=3",
                 "experiment.sweeps=sigma_loc_m, sigma_act_m",
                 "experiment.sigma_loc_values_m=0, 0.1",
                 "experiment.sigma_act_values_m=0.04",
                 "experiment.plots=false",
                 "placement.max_iterations=40"};
  return o;
}

class ExperimentShards : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = fs::path(::testing::TempDir()) / ("losmimo_shard_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    ASSERT_EQ(losmimo::test_support::run_experiment(tiny(root_ / "single", 2)), 0);
    for (int i = 0; i < kShards; ++i) {
      losmimo::apps::ExperimentOptions o = tiny(shard_dir(i), 1 + i % 2);
      o.shard = std::to_string(i) + "/" + std::to_string(kShards);
      ASSERT_EQ(losmimo::test_support::run_experiment(o), 0) << *o.shard;
    }
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  static fs::path shard_dir(int i) { return root_ / ("shard" + std::to_string(i)); }
  static fs::path root_;
};
fs::path ExperimentShards::root_;
}  // namespace

TEST(ExperimentShard, ParseShard_AcceptsIOfNAndRejectsTheRest) {
  EXPECT_EQ(losmimo::experiment::parse_shard("0/1"), std::make_pair(0, 1));
  EXPECT_EQ(losmimo::experiment::parse_shard("3/4"), std::make_pair(3, 4));
  for (const char* bad : {"0/0", "3/2", "2/2", "x/y", "1", "/2", "1/", "-1/2", "1/-2", " 1/2", "1/2/3", "1.0/2"}) {
    EXPECT_THROW(losmimo::experiment::parse_shard(bad), losmimo::common::InputError) << bad;
  }
}

TEST(ExperimentShard, BadShardOption_ExitsWith2BeforeAnyWork) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("losmimo_badshard_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  for (const char* bad : {"0/0", "3/2", "x/y"}) {
    losmimo::apps::ExperimentOptions o = tiny(dir, 1);
    o.shard = bad;
    std::string err;
    EXPECT_EQ(losmimo::test_support::run_experiment(o, &err), 2) << bad;
    EXPECT_NE(err.find(bad), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir)) << bad;
  }
}

TEST_F(ExperimentShards, Merge_IsByteIdenticalToOneProcess) {
  const fs::path merged = root_ / "merged";
  ASSERT_EQ(losmimo::test_support::run_merge({shard_dir(0), shard_dir(1), shard_dir(2)}, merged), 0);
  for (const char* f : {"trials.csv", "summary.csv", "positions.csv", "traces.csv"}) {
    ASSERT_GT(read_file(root_ / "single" / f).size(), 100u) << f;
    EXPECT_EQ(read_file(merged / f), read_file(root_ / "single" / f)) << f;
  }
}

TEST_F(ExperimentShards, ShardsInAnyOrder_MergeTheSame) {
  const fs::path merged = root_ / "merged_reordered";
  ASSERT_EQ(losmimo::test_support::run_merge({shard_dir(2), shard_dir(0), shard_dir(1)}, merged), 0);
  EXPECT_EQ(read_file(merged / "trials.csv"), read_file(root_ / "single" / "trials.csv"));
  EXPECT_EQ(read_file(merged / "summary.csv"), read_file(root_ / "single" / "summary.csv"));
}

TEST_F(ExperimentShards, EveryJobRunsInExactlyOneShard) {
  std::size_t rows = 0;
  for (int i = 0; i < kShards; ++i) {
    std::ifstream in(shard_dir(i) / "records.csv");
    const losmimo::experiment::RecordLines lines =
        losmimo::experiment::read_records(in, "records.csv", losmimo::experiment::RecordsMode::kComplete);
    for (const auto& [point, records] : lines.points) {
      for (const losmimo::experiment::TrialRecord& r : records) {
        EXPECT_EQ((point * 3 + r.trial) % kShards, i) << "point " << point << " trial " << r.trial;
        ++rows;
      }
    }
  }
  // 3 points x 3 trials x 5 algorithms
  EXPECT_EQ(rows, 45u);
}

TEST_F(ExperimentShards, MissingShard_Exits2NamingIt) {
  std::string err;
  EXPECT_EQ(losmimo::test_support::run_merge({shard_dir(0), shard_dir(2)}, root_ / "m_missing", &err), 2);
  EXPECT_NE(err.find("missing shard(s) 1 of 3"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(root_ / "m_missing" / "trials.csv"));
}

TEST_F(ExperimentShards, RepeatedShard_Exits2) {
  std::string err;
  EXPECT_EQ(losmimo::test_support::run_merge({shard_dir(0), shard_dir(1), shard_dir(1), shard_dir(2)},
                                             root_ / "m_twice", &err),
            2);
  EXPECT_NE(err.find("given twice"), std::string::npos) << err;
}

TEST_F(ExperimentShards, NotAShardFolder_Exits2) {
  std::string err;
  EXPECT_EQ(
      losmimo::test_support::run_merge({shard_dir(0), root_ / "single", shard_dir(2)}, root_ / "m_notshard", &err), 2);
  EXPECT_NE(err.find("holds a finished experiment, not a shard"), std::string::npos) << err;
}

TEST_F(ExperimentShards, ShardOfAnotherConfig_Exits2) {
  const fs::path other = root_ / "other_seed";
  losmimo::apps::ExperimentOptions o = tiny(other, 1);
  o.overrides.push_back("experiment.seed=7");
  o.shard = "1/3";
  ASSERT_EQ(losmimo::test_support::run_experiment(o), 0);
  std::string err;
  EXPECT_EQ(losmimo::test_support::run_merge({shard_dir(0), other, shard_dir(2)}, root_ / "m_other", &err), 2);
  EXPECT_NE(err.find("differs"), std::string::npos) << err;
  EXPECT_NE(err.find("seed"), std::string::npos) << err;
}

TEST_F(ExperimentShards, ShardsOfAnotherCount_Exit2) {
  const fs::path other = root_ / "other_count";
  losmimo::apps::ExperimentOptions o = tiny(other, 1);
  o.shard = "1/2";
  ASSERT_EQ(losmimo::test_support::run_experiment(o), 0);
  std::string err;
  EXPECT_EQ(losmimo::test_support::run_merge({shard_dir(0), other}, root_ / "m_count", &err), 2);
  EXPECT_NE(err.find("of 2"), std::string::npos) << err;
}

TEST_F(ExperimentShards, TruncatedShardRecords_Exit2) {
  const fs::path copy = root_ / "truncated";
  fs::create_directories(copy);
  for (const char* f : {"config.ini", "losmimo-run.ini"}) fs::copy_file(shard_dir(1) / f, copy / f);
  const std::string records = read_file(shard_dir(1) / "records.csv");
  std::ofstream(copy / "records.csv", std::ios::binary) << records.substr(0, records.size() / 2);
  // The manifest catches the change first; without it (listing nothing) the records do.
  std::string err;
  EXPECT_EQ(losmimo::test_support::run_merge({shard_dir(0), copy, shard_dir(2)}, root_ / "m_truncated", &err), 2);
}

namespace {
// A copy of shard i whose manifest keeps only the lines for which `keep` is true, plus `extra`
// (in its [shard] section).
fs::path copy_shard(const fs::path& root, int i, const std::string& name, bool (*keep)(const std::string&),
                    const std::string& extra = "") {
  const fs::path src = fs::path(root) / ("shard" + std::to_string(i));
  const fs::path dst = fs::path(root) / name / ("shard" + std::to_string(i));
  fs::create_directories(dst);
  for (const char* f : {"config.ini", "records.csv"})
    fs::copy_file(src / f, dst / f, fs::copy_options::overwrite_existing);
  std::istringstream in(read_file(src / "losmimo-run.ini"));
  std::ofstream out(dst / "losmimo-run.ini", std::ios::binary);
  for (std::string line; std::getline(in, line);) {
    if (keep(line)) out << line << "\n";
    if (line == "[shard]") out << extra;
  }
  return dst;
}
bool keep_all(const std::string&) { return true; }
bool drop_timing(const std::string& line) { return line.rfind("wall_s", 0) != 0 && line.rfind("threads", 0) != 0; }
bool drop_wall(const std::string& line) { return line.rfind("wall_s", 0) != 0; }

double shard_wall_s(const fs::path& dir) {
  std::istringstream in(read_file(dir / "losmimo-run.ini"));
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("wall_s = ", 0) == 0) return std::stod(line.substr(9));
  }
  ADD_FAILURE() << dir << ": no wall_s";
  return -1.0;
}
std::string one_decimal(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}
}  // namespace

TEST_F(ExperimentShards, MergedReport_GivesTheShardsOwnTiming) {
  double slowest_s = 0.0, sum_s = 0.0;
  for (int i = 0; i < kShards; ++i) {
    const double s = shard_wall_s(shard_dir(i));
    slowest_s = std::max(slowest_s, s);
    sum_s += s;
  }
  ASSERT_EQ(losmimo::test_support::run_merge({shard_dir(0), shard_dir(1), shard_dir(2)}, root_ / "m_timing"), 0);
  const std::string report = read_file(root_ / "m_timing" / "report.md");
  // Shards 0 and 2 ran 1 thread, shard 1 ran 2 (the fixture).
  const std::string expected = "merged from 3 shards of 1 to 2 threads: slowest " + one_decimal(slowest_s) +
                               " s wall, " + one_decimal(sum_s) + " s wall summed over shards; merge ";
  EXPECT_NE(report.find(expected), std::string::npos) << expected << "\n" << report.substr(0, 400);
}

TEST_F(ExperimentShards, ShardsWithoutTiming_StillMergeAndSaySo) {
  std::vector<fs::path> dirs;
  for (int i = 0; i < kShards; ++i) dirs.push_back(copy_shard(root_, i, "untimed", i == 1 ? drop_timing : keep_all));
  ASSERT_EQ(losmimo::test_support::run_merge(dirs, root_ / "m_untimed"), 0);
  EXPECT_EQ(read_file(root_ / "m_untimed" / "summary.csv"), read_file(root_ / "single" / "summary.csv"));
  const std::string report = read_file(root_ / "m_untimed" / "report.md");
  EXPECT_NE(report.find("merged from 3 shards (their timing was not recorded); merge "), std::string::npos)
      << report.substr(0, 400);
}

TEST_F(ExperimentShards, BadShardWallTime_Exits2NamingTheKey) {
  for (const char* bad : {"wall_s = -1\n", "wall_s = nan\n", "wall_s = soon\n"}) {
    std::vector<fs::path> dirs;
    for (int i = 0; i < kShards; ++i) {
      dirs.push_back(i == 2 ? copy_shard(root_, i, "badwall", drop_wall, bad) : shard_dir(i));
    }
    std::string err;
    EXPECT_EQ(losmimo::test_support::run_merge(dirs, root_ / "m_badwall", &err), 2) << bad;
    EXPECT_NE(err.find("wall_s"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(root_ / "m_badwall" / "summary.csv")) << bad;
  }
}

namespace {
bool drop_isa(const std::string& line) { return line.rfind("isa", 0) != 0; }
// An instruction-set name that is not this process's.
std::string another_isa() { return lp::active_isa() == lp::Isa::kSse2 ? "avx2" : "sse2"; }
}  // namespace

TEST_F(ExperimentShards, ShardManifest_RecordsTheKernelsInstructionSet) {
  for (int i = 0; i < kShards; ++i) {
    EXPECT_NE(read_file(shard_dir(i) / "losmimo-run.ini").find("\nisa = " + lp::to_string(lp::active_isa()) + "\n"),
              std::string::npos)
        << i;
  }
  // AND: a merge of shards on one instruction set names it and adds no note.
  std::string err;
  ASSERT_EQ(losmimo::test_support::run_merge({shard_dir(0), shard_dir(1), shard_dir(2)}, root_ / "m_isa", &err), 0);
  EXPECT_EQ(err.find("note:"), std::string::npos) << err;
  EXPECT_NE(read_file(root_ / "m_isa" / "report.md").find("; " + lp::to_string(lp::active_isa()) + " kernels"),
            std::string::npos);
}

TEST_F(ExperimentShards, ShardsOnDifferentInstructionSets_MergeWithANote) {
  // GIVEN: shard 1 says it ran on another instruction set (experiment_isa_test.cpp runs one so).
  const std::string other = another_isa(), mine = lp::to_string(lp::active_isa());
  std::vector<fs::path> dirs;
  for (int i = 0; i < kShards; ++i) {
    dirs.push_back(i == 1 ? copy_shard(root_, i, "mixed_isa", drop_isa, "isa = " + other + "\n") : shard_dir(i));
  }
  std::string err;
  ASSERT_EQ(losmimo::test_support::run_merge(dirs, root_ / "m_mixed_isa", &err), 0) << err;
  // THEN: the merge says so, naming both and how many shards ran on each; the records merge as ever.
  EXPECT_NE(err.find("losmimo-experiment merge: note: the shards ran the placement kernels on different instruction "
                     "sets"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find(other + " in 1 shard"), std::string::npos) << err;
  EXPECT_NE(err.find(mine + " in 2 shards"), std::string::npos) << err;
  EXPECT_NE(err.find("1e-9 relative"), std::string::npos) << err;
  EXPECT_EQ(read_file(root_ / "m_mixed_isa" / "summary.csv"), read_file(root_ / "single" / "summary.csv"));
  EXPECT_NE(read_file(root_ / "m_mixed_isa" / "report.md").find("; kernels "), std::string::npos);
}

TEST_F(ExperimentShards, BadShardInstructionSet_Exits2NamingTheKeyAndValue) {
  for (const char* bad : {"neon", "AVX512", ""}) {
    std::vector<fs::path> dirs;
    for (int i = 0; i < kShards; ++i) {
      dirs.push_back(i == 2 ? copy_shard(root_, i, "bad_isa", drop_isa, std::string("isa = ") + bad + "\n")
                            : shard_dir(i));
    }
    std::string err;
    EXPECT_EQ(losmimo::test_support::run_merge(dirs, root_ / "m_bad_isa", &err), 2) << bad;
    EXPECT_NE(err.find("isa = " + std::string(bad) + ": must be sse2, avx2 or avx512"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(root_ / "m_bad_isa" / "summary.csv")) << bad;
  }
}
