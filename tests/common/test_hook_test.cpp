// The pause points of common/test_hook.h: the test suite's build has them, and the variant a
// build without them gets (LOSMIMO_TEST_HOOKS OFF, as for a release) ignores LOSMIMO_TEST_PAUSE.
// This file compiles that no-op variant (LOSMIMO_TEST_HOOKS defined 0 before the header); it
// lives in its own inline namespace, so it cannot collide with the library's real hook.
#define LOSMIMO_TEST_HOOKS 0
#include "losmimo/placement/common/test_hook.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>

namespace losmimo::common {
namespace {

constexpr auto kDeadline = std::chrono::seconds(10);  // a real pause point would wait forever

TEST(TestHook, TestSuiteBuild_HasThePausePoints) {
  // The interruption tests (tests/apps/pause_point.h, the rawlog sandbox) need them.
  EXPECT_TRUE(test_hooks_compiled_in()) << "configure the tests with -DLOSMIMO_TEST_HOOKS=ON (the default)";
}

TEST(TestHook, WithoutHooks_PauseVariableIsIgnored) {
  // GIVEN: the variable names the very point called, with a mark file, in a child process
  const std::string mark =
      (std::filesystem::temp_directory_path() / ("losmimo_test_hook_" + std::to_string(::getpid()) + ".paused"))
          .string();
  std::filesystem::remove(mark);
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::setenv("LOSMIMO_TEST_PAUSE", "check.point", 1);
    ::setenv("LOSMIMO_TEST_PAUSE_MARK", mark.c_str(), 1);
    test_pause_point("check.point");
    test_pause_point("check.point");
    ::_exit(0);
  }
  // WHEN: the child runs past the point (a hook would stop it there for good)
  int status = 0;
  bool ended = false;
  const auto deadline = std::chrono::steady_clock::now() + kDeadline;
  while (!ended && std::chrono::steady_clock::now() < deadline) {
    ended = ::waitpid(pid, &status, WNOHANG) == pid;
    if (!ended) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  if (!ended) {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
  }
  // THEN: it ended normally and never marked a pause
  EXPECT_TRUE(ended) << "the no-op hook paused";
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_FALSE(std::filesystem::exists(mark));
  std::filesystem::remove(mark);
}

}  // namespace
}  // namespace losmimo::common
