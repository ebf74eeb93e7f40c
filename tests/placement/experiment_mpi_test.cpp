// MPI mode: `mpirun -np 2 losmimo-experiment ...` on loopback writes byte-identical results to
// a single-process run. Skipped when mpirun or the app's MPI support is absent.
#include <gtest/gtest.h>

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

namespace losmimo::test {

// Starts argv[0] with argv; stdout/stderr go to `log_path`. Returns the pid (-1 on failure).
inline pid_t spawn(const std::vector<std::string>& argv, const std::string& log_path) {
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  const int fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd >= 0) {
    ::dup2(fd, STDOUT_FILENO);
    ::dup2(fd, STDERR_FILENO);
    ::close(fd);
  }
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  ::execvp(args[0], args.data());
  ::_exit(127);
}

// Waits for the child; its exit code, or 128 + signal.
inline int wait_for(pid_t pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

inline int run_process(const std::vector<std::string>& argv, const std::string& log_path) {
  const pid_t pid = spawn(argv, log_path);
  return pid < 0 ? -1 : wait_for(pid);
}

// The first executable `name` on PATH, or "".
inline std::string find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t end = dirs.find(':', start);
    const std::string dir = dirs.substr(start, end == std::string::npos ? std::string::npos : end - start);
    const std::string candidate = (dir.empty() ? "." : dir) + "/" + name;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return "";
}

}  // namespace losmimo::test

namespace fs = std::filesystem;
namespace lt = losmimo::test;

namespace {
std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

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
