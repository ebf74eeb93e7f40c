// support/dependencies.h: when a missing dependency skips, fails or lets the test run, and
// dpkg's answer for packages that are and are not installed.
#include "support/dependencies.h"

#include <gtest/gtest.h>

#include <string>

namespace losmimo::test_support {
namespace {

TEST(DependencyRequirement, Present_RunsWhateverThePackage) {
  EXPECT_EQ(requirement(true, false, "mrpt-common", "x").verdict, Verdict::kRun);
  EXPECT_EQ(requirement(true, true, "mrpt-common", "x").verdict, Verdict::kRun);
  EXPECT_TRUE(requirement(true, true, "mrpt-common", "x").message.empty());
}

TEST(DependencyRequirement, MissingWithoutItsPackage_SkipsNamingFileAndPackage) {
  const Requirement r = requirement(false, false, "mrpt-common", "/usr/share/mrpt/datasets/a.rawlog");
  EXPECT_EQ(r.verdict, Verdict::kSkip);
  EXPECT_NE(r.message.find("/usr/share/mrpt/datasets/a.rawlog is missing"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("mrpt-common is not installed"), std::string::npos) << r.message;
}

TEST(DependencyRequirement, MissingThoughItsPackageIsInstalled_FailsNamingFileAndPackage) {
  const Requirement r = requirement(false, true, "mrpt-apps", "the program rawlog-edit on PATH");
  EXPECT_EQ(r.verdict, Verdict::kFail);
  EXPECT_NE(r.message.find("the program rawlog-edit on PATH is missing"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("mrpt-apps is installed"), std::string::npos) << r.message;
}

TEST(DebianPackageInstalled, NoSuchPackageOrNotAName_IsNotInstalled) {
  EXPECT_FALSE(debian_package_installed("losmimo-no-such-package"));
  EXPECT_FALSE(debian_package_installed("dpkg; true"));  // not a package name: never run
  EXPECT_FALSE(debian_package_installed(""));
}

TEST(DebianPackageInstalled, Dpkg_IsInstalledWhereverDpkgQueryRuns) {
  // dpkg ships dpkg-query: on a Debian system both are there, elsewhere this skips.
  LOSMIMO_REQUIRE_PROGRAM("dpkg-query", "dpkg");
  EXPECT_TRUE(debian_package_installed("dpkg"));
}

}  // namespace
}  // namespace losmimo::test_support
