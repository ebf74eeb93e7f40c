// losmimo-experiment's numeric options (the real binary): a value out of range exits 2 with a
// message that names the option, the value and the integer range it must lie in.
#include <gtest/gtest.h>

#include "support/child_process.h"
#include "support/files.h"

#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;
namespace lt = losmimo::test_support;

TEST(ExperimentOptions, TrialsAndThreadsOutOfRange_Exit2NamingTheOptionValueAndIntegerRange) {
  const fs::path root = fs::path(::testing::TempDir()) / ("losmimo_options_" + std::to_string(::getpid()));
  fs::create_directories(root);
  struct Case {
    std::string option, value, message;
  };
  const std::vector<Case> cases = {
      {"--trials", "0", "--trials: Value 0 not in range 1 to 2147483647"},
      {"--trials", "-3", "--trials: Value -3 not in range 1 to 2147483647"},
      {"--threads", "-1", "--threads: Value -1 not in range 0 to 2147483647"},
  };
  for (const Case& c : cases) {
    const fs::path log = root / "out.log";
    const fs::path out = root / "never";
    EXPECT_EQ(lt::run_process({LOSMIMO_EXPERIMENT_APP, c.option, c.value, "--out", out.string()}, log.string()), 2)
        << c.option << " " << c.value;
    const std::string text = lt::read_file(log);
    EXPECT_NE(text.find(c.message), std::string::npos) << text;
    EXPECT_EQ(text.find("0.000000"), std::string::npos) << "bounds printed as doubles: " << text;
    EXPECT_FALSE(fs::exists(out)) << "a refused run writes nothing";
  }
  fs::remove_all(root);
}
