// The placement kernels compute the same bits on every instruction set (kernels.h): the real
// losmimo-experiment forced to SSE2 (LOSMIMO_ISA) writes the same bytes as on the widest set this
// CPU runs, shards computed on the two merge to those bytes with the merge's note, and a
// LOSMIMO_ISA the CPU cannot run stops every app with exit code 2 before any work.
#include <gtest/gtest.h>

#include "support/child_process.h"
#include "support/dependencies.h"
#include "support/files.h"

#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include "losmimo/placement/isa.h"

namespace fs = std::filesystem;
namespace lp = losmimo::placement;
namespace lt = losmimo::test_support;

namespace {

// Every algorithm, localization and actuation errors, 2 trials of 3 points.
std::vector<std::string> app_args(const std::string& isa, const fs::path& out, const std::string& shard = "") {
  std::vector<std::string> a = {"env",
                                std::string(lp::kIsaEnvironmentVariable) + "=" + isa,
                                LOSMIMO_EXPERIMENT_APP,
                                "--out",
                                out.string(),
                                "--threads",
                                "2",
                                "--trials",
                                "2",
                                "--set",
                                "experiment.sweeps=sigma_loc_m, sigma_act_m",
                                "--set",
                                "experiment.sigma_loc_values_m=0, 0.1",
                                "--set",
                                "experiment.sigma_act_values_m=0.06",
                                "--set",
                                "experiment.plots=false",
                                "--set",
                                "placement.max_iterations=150"};
  if (!shard.empty()) a.insert(a.end(), {"--shard", shard});
  return a;
}

class ExperimentIsa : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::path(::testing::TempDir()) / ("losmimo_isa_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }
  int run(const std::vector<std::string>& argv, const std::string& name) {
    return lt::run_process(argv, (root_ / (name + ".log")).string());
  }
  std::string log(const std::string& name) const { return lt::read_file(root_ / (name + ".log")); }
  fs::path root_;
};

}  // namespace

TEST_F(ExperimentIsa, ForcedSse2_SameBytesAsTheWidest_AndMixedShardsMergeToThem) {
  const std::string widest = lp::to_string(lp::supported_isas().back());
  if (widest == "sse2") LOSMIMO_SKIP_MACHINE_DEPENDENT("this CPU runs SSE2 only: nothing to compare");
  // GIVEN: the same run on SSE2 and on the widest instruction set.
  ASSERT_EQ(run(app_args("sse2", root_ / "sse2"), "sse2"), 0) << log("sse2");
  ASSERT_EQ(run(app_args(widest, root_ / "wide"), "wide"), 0) << log("wide");
  // THEN: byte-identical results; each report names its kernels.
  for (const char* f : {"trials.csv", "summary.csv", "positions.csv", "traces.csv"}) {
    ASSERT_GT(lt::read_file(root_ / "wide" / f).size(), 100u) << f;
    EXPECT_EQ(lt::read_file(root_ / "sse2" / f), lt::read_file(root_ / "wide" / f)) << f;
  }
  EXPECT_NE(lt::read_file(root_ / "sse2" / "report.md").find(", sse2 kernels"), std::string::npos);
  EXPECT_NE(lt::read_file(root_ / "wide" / "report.md").find(", " + widest + " kernels"), std::string::npos);

  // WHEN: shard 0 runs on SSE2, shard 1 on the widest, and they merge.
  ASSERT_EQ(run(app_args("sse2", root_ / "s0", "0/2"), "s0"), 0) << log("s0");
  ASSERT_EQ(run(app_args(widest, root_ / "s1", "1/2"), "s1"), 0) << log("s1");
  ASSERT_EQ(run({LOSMIMO_EXPERIMENT_APP, "merge", (root_ / "s0").string(), (root_ / "s1").string(), "--out",
                 (root_ / "merged").string()},
                "merge"),
            0)
      << log("merge");
  // THEN: the merge notes the two instruction sets and its files are the one-process bytes.
  EXPECT_NE(log("merge").find("note: the shards ran the placement kernels on different instruction sets (" + widest +
                              " in 1 shard, sse2 in 1 shard)"),
            std::string::npos)
      << log("merge");
  for (const char* f : {"trials.csv", "summary.csv", "positions.csv"}) {
    EXPECT_EQ(lt::read_file(root_ / "merged" / f), lt::read_file(root_ / "wide" / f)) << f;
  }
}

TEST_F(ExperimentIsa, UnknownOrUnsupportedIsa_EveryAppExits2BeforeAnyWork) {
  std::vector<std::string> bad = {"bogus", "AVX2"};
  for (const lp::Isa isa : {lp::Isa::kAvx2, lp::Isa::kAvx512}) {
    if (!lp::isa_supported(isa)) bad.push_back(lp::to_string(isa));
  }
  const std::string source = LOSMIMO_SOURCE_DIR;
  for (const std::string& value : bad) {
    const std::string env = std::string(lp::kIsaEnvironmentVariable) + "=" + value;
    const std::vector<std::vector<std::string>> apps = {
        app_args(value, root_ / "out"),
        {"env", env, LOSMIMO_EVAL_APP, "--positions", source + "/datasets/examples/ura_optimal_16.csv"},
        {"env", env, LOSMIMO_RECORD_APP, "--out", (root_ / "out.rawlog").string()},
        {"env", env, LOSMIMO_REPLAY_APP, source + "/datasets/missions/nominal/mission.rawlog", "--out",
         (root_ / "out").string()}};
    for (const std::vector<std::string>& argv : apps) {
      const int code = run(argv, "bad");
      const std::string text = log("bad");
      fs::remove(root_ / "bad.log");
      EXPECT_EQ(code, 2) << value << " " << argv[2] << "\n" << text;
      EXPECT_NE(text.find("LOSMIMO_ISA = '" + value + "'"), std::string::npos) << text;
      // AND: nothing written, not even a partial file.
      EXPECT_TRUE(fs::is_empty(root_)) << value << " " << argv[2];
    }
  }
}
