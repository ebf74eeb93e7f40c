// MPI mode: `mpirun -np 2 losmimo-experiment ...` on loopback writes byte-identical results to
// a single-process run. Skipped when mpirun or the app's MPI support is absent.
#include <gtest/gtest.h>

#include "support/child_process.h"
#include "support/files.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

// Runs the real losmimo-experiment binary (LOSMIMO_EXPERIMENT_APP) as a child process.
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <fcntl.h>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>



namespace fs = std::filesystem;
namespace lt = losmimo::test_support;

namespace {
using losmimo::test_support::read_file;

std::vector<std::string> app_args(const fs::path& out) {
  return {LOSMIMO_EXPERIMENT_APP, "--out", out.string(), "--threads", "1", "--trials", "3",
          "--set", "experiment.sweeps=sigma_loc_m, sigma_act_m",
          "--set", "experiment.sigma_loc_values_m=0, 0.1",
          "--set", "experiment.sigma_act_values_m=0.04",
          "--set", "experiment.plots=false",
          "--set", "placement.max_iterations=150"};
}
}  // namespace

TEST(ExperimentMpi, TwoRanksOnLoopback_MatchOneProcessByteForByte) {
#if !LOSMIMO_APP_HAS_MPI
  GTEST_SKIP() << "losmimo-experiment was built without MPI (apt-get install libopenmpi-dev openmpi-bin)";
#endif
  const std::string mpirun = lt::find_on_path("mpirun");
  if (mpirun.empty()) GTEST_SKIP() << "mpirun not on PATH (apt-get install openmpi-bin): MPI test skipped";

  const fs::path root = fs::path(::testing::TempDir()) / ("losmimo_mpi_" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root);
  ASSERT_EQ(lt::run_process(app_args(root / "single"), (root / "single.log").string()), 0)
      << read_file(root / "single.log");

  // Loopback only, no shared-memory transport (containers often forbid its single-copy
  // mechanism); root is allowed (CI containers run as root).
  ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
  ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  ::setenv("OMPI_MCA_btl", "self,tcp", 1);
  ::setenv("OMPI_MCA_btl_tcp_if_include", "lo", 1);
  ::setenv("OMPI_MCA_oob_tcp_if_include", "lo", 1);
  std::vector<std::string> argv = {mpirun, "--oversubscribe", "--allow-run-as-root", "-np", "2"};
  const std::vector<std::string> app = app_args(root / "mpi");
  argv.insert(argv.end(), app.begin(), app.end());
  ASSERT_EQ(lt::run_process(argv, (root / "mpi.log").string()), 0) << read_file(root / "mpi.log");

  for (const char* f : {"trials.csv", "summary.csv", "positions.csv", "traces.csv"}) {
    ASSERT_GT(read_file(root / "single" / f).size(), 100u) << f;
    EXPECT_EQ(read_file(root / "mpi" / f), read_file(root / "single" / f)) << f;
  }
  fs::remove_all(root);
}
