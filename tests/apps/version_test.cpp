// --version on every app (the real binaries): exit code 0 and the one line
// "losmimo <version> (<isa> kernels)", the version being the project's and the instruction set
// the one the kernels run on (LOSMIMO_ISA forces it).
#include <gtest/gtest.h>

#include "support/child_process.h"
#include "support/files.h"

#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include <unistd.h>

#include "losmimo/placement/isa.h"

namespace fs = std::filesystem;
namespace lp = losmimo::placement;
namespace lt = losmimo::test_support;

namespace {

const std::vector<std::string> kApps = {LOSMIMO_EXPERIMENT_APP, LOSMIMO_EVAL_APP, LOSMIMO_RECORD_APP,
                                        LOSMIMO_REPLAY_APP};

class AppVersion : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::path(::testing::TempDir()) / ("losmimo_version_" + std::to_string(::getpid()));
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }
  // The app's exit code; its output in `out`.
  int run(const std::vector<std::string>& argv, std::string& out) {
    const fs::path log = root_ / "version.log";
    const int code = lt::run_process(argv, log.string());
    out = lt::read_file(log);
    return code;
  }
  fs::path root_;
};

}  // namespace

TEST_F(AppVersion, EveryApp_PrintsVersionAndKernels_ExitZero) {
  const std::string isa = lp::to_string(lp::active_isa());  // the tests run with the apps' environment
  const std::regex format(R"(losmimo [0-9]+\.[0-9]+\.[0-9]+ \((sse2|avx2|avx512) kernels\)\n)");
  for (const std::string& app : kApps) {
    std::string out;
    EXPECT_EQ(run({app, "--version"}, out), 0) << app << ": " << out;
    EXPECT_TRUE(std::regex_match(out, format)) << app << ": '" << out << "'";
    EXPECT_EQ(out, std::string("losmimo ") + LOSMIMO_VERSION + " (" + isa + " kernels)\n") << app;
  }
}

TEST_F(AppVersion, ForcedIsa_IsTheOneNamed) {
  for (const std::string& app : kApps) {
    std::string out;
    EXPECT_EQ(run({"env", std::string(lp::kIsaEnvironmentVariable) + "=sse2", app, "--version"}, out), 0) << out;
    EXPECT_EQ(out, std::string("losmimo ") + LOSMIMO_VERSION + " (sse2 kernels)\n") << app;
  }
}

TEST_F(AppVersion, OtherOptionsAreIgnored_RequiredOnesToo) {
  // losmimo-replay requires its rawlog and losmimo-eval --positions: --version alone still answers.
  std::string out;
  EXPECT_EQ(run({LOSMIMO_REPLAY_APP, "--version"}, out), 0) << out;
  EXPECT_EQ(run({LOSMIMO_EVAL_APP, "--version", "--csv"}, out), 0) << out;
  EXPECT_EQ(out.rfind("losmimo ", 0), 0u) << out;
}
