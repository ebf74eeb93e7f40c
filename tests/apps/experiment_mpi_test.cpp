// MPI mode: `mpirun -np 2 losmimo-experiment ...` on loopback writes byte-identical results to
// a single-process run, also when the two ranks run the kernels on different instruction sets
// (with a note). Runs the real binary (LOSMIMO_EXPERIMENT_APP). Without mpirun or the app's MPI
// support: skipped when openmpi-bin / libopenmpi-dev is not installed, failed when it is
// (support/dependencies.h).
#include <gtest/gtest.h>

#include "support/child_process.h"
#include "support/dependencies.h"
#include "support/files.h"

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include "losmimo/placement/isa.h"

namespace fs = std::filesystem;
namespace lt = losmimo::test_support;
namespace lp = losmimo::placement;

namespace {
using losmimo::test_support::read_file;

std::vector<std::string> app_args(const fs::path& out) {
  return {LOSMIMO_EXPERIMENT_APP,
          "--out",
          out.string(),
          "--threads",
          "1",
          "--trials",
          "3",
          "--set",
          "experiment.sweeps=sigma_loc_m, sigma_act_m",
          "--set",
          "experiment.sigma_loc_values_m=0, 0.1",
          "--set",
          "experiment.sigma_act_values_m=0.04",
          "--set",
          "experiment.plots=false",
          "--set",
          "placement.max_iterations=150"};
}

class ExperimentMpi : public ::testing::Test {
 protected:
  void SetUp() override {
#if !LOSMIMO_APP_HAS_MPI
    LOSMIMO_REQUIRE(false, "libopenmpi-dev", "MPI in losmimo-experiment (CMake found no MPI at configure time)");
#endif
    mpirun_ = lt::find_on_path("mpirun");
    LOSMIMO_REQUIRE(!mpirun_.empty(), "openmpi-bin", "the program mpirun on PATH");
    root_ = fs::path(::testing::TempDir()) / ("losmimo_mpi_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
    ASSERT_EQ(lt::run_process(app_args(root_ / "single"), (root_ / "single.log").string()), 0)
        << read_file(root_ / "single.log");
    // Loopback only, no shared-memory transport (containers often forbid its single-copy
    // mechanism); root is allowed (CI containers run as root).
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    ::setenv("OMPI_MCA_btl", "self,tcp", 1);
    ::setenv("OMPI_MCA_btl_tcp_if_include", "lo", 1);
    ::setenv("OMPI_MCA_oob_tcp_if_include", "lo", 1);
  }
  void TearDown() override {
    if (!root_.empty()) fs::remove_all(root_);
  }
  std::vector<std::string> mpirun() const { return {mpirun_, "--oversubscribe", "--allow-run-as-root"}; }
  void expect_same_files_as_single(const fs::path& dir) const {
    for (const char* f : {"trials.csv", "summary.csv", "positions.csv", "traces.csv"}) {
      ASSERT_GT(read_file(root_ / "single" / f).size(), 100u) << f;
      EXPECT_EQ(read_file(dir / f), read_file(root_ / "single" / f)) << f;
    }
  }
  std::string mpirun_;
  fs::path root_;
};
}  // namespace

TEST_F(ExperimentMpi, TwoRanksOnLoopback_MatchOneProcessByteForByte) {
  std::vector<std::string> argv = mpirun();
  argv.insert(argv.end(), {"-np", "2"});
  const std::vector<std::string> app = app_args(root_ / "mpi");
  argv.insert(argv.end(), app.begin(), app.end());
  ASSERT_EQ(lt::run_process(argv, (root_ / "mpi.log").string()), 0) << read_file(root_ / "mpi.log");
  expect_same_files_as_single(root_ / "mpi");
  EXPECT_EQ(read_file(root_ / "mpi.log").find("note:"), std::string::npos) << read_file(root_ / "mpi.log");
}

TEST_F(ExperimentMpi, RanksOnDifferentInstructionSets_SameBytesWithANote) {
  const std::string widest = lp::to_string(lp::supported_isas().back());
  if (widest == "sse2") LOSMIMO_SKIP_MACHINE_DEPENDENT("this CPU runs SSE2 only: nothing to mix");
  // Rank 0 forced to SSE2, rank 1 on the widest (MPMD: one app context per rank).
  std::vector<std::string> argv = mpirun();
  const std::vector<std::string> app = app_args(root_ / "mpi_mixed");
  for (const std::string& isa : {std::string("sse2"), widest}) {
    if (isa != "sse2") argv.push_back(":");
    argv.insert(argv.end(), {"-np", "1", "env", std::string(lp::kIsaEnvironmentVariable) + "=" + isa});
    argv.insert(argv.end(), app.begin(), app.end());
  }
  ASSERT_EQ(lt::run_process(argv, (root_ / "mixed.log").string()), 0) << read_file(root_ / "mixed.log");
  expect_same_files_as_single(root_ / "mpi_mixed");
  const std::string log = read_file(root_ / "mixed.log");
  EXPECT_NE(log.find("note: the ranks ran the placement kernels on different instruction sets (" + widest +
                     " in 1 rank, sse2 in 1 rank)"),
            std::string::npos)
      << log;
  EXPECT_NE(read_file(root_ / "mpi_mixed" / "report.md").find(widest + "+sse2 kernels"), std::string::npos);
}
