#pragma once
// Tests that need something from outside the build: a skip only when no package install would
// give it, a failure when the package that provides it is installed and it is still missing.
//
//   LOSMIMO_REQUIRE(present, package, what)     in a TEST body or SetUp():
//     present                       -> the test goes on;
//     missing, package not installed -> GTEST_SKIP, naming `what` and the Debian package;
//     missing, package installed     -> FAIL, naming `what` and the package (scripts/setup
//                                       installs it, so a wrong path or a broken install fails).
//   LOSMIMO_REQUIRE_FILE(path, package)          present = std::filesystem::exists(path)
//   LOSMIMO_REQUIRE_PROGRAM(name, package)       present = an executable `name` on PATH
//   LOSMIMO_SKIP_MACHINE_DEPENDENT(reason)       a skip no package can lift (the CPU, a
//                                                sanitizer build): the message starts with
//                                                kMachineDependentTag, which
//                                                scripts/check-no-skips reports but accepts.
//
// "Installed" is dpkg's own word: `dpkg-query -W -f='${db:Status-Status}' PACKAGE` prints
// "installed" (no dpkg-query, or any other status, counts as not installed). It is asked at run
// time, and only when something is missing: a configure-time fact would go stale when a package
// is installed or removed after configuring, and a run with everything present never calls dpkg.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include <unistd.h>

#include "support/child_process.h"

namespace losmimo::test_support {

inline constexpr const char* kMachineDependentTag = "machine-dependent skip: ";

// dpkg's db:Status-Status of `package` is "installed". Cached per package for the process.
inline bool debian_package_installed(const std::string& package) {
  static std::map<std::string, bool> cache;
  if (const auto it = cache.find(package); it != cache.end()) return it->second;
  // Debian package names are [a-z0-9][a-z0-9+.-]+: anything else is no package (and never
  // reaches the shell).
  bool valid = package.size() >= 2;
  for (const char c : package) {
    valid = valid && ((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '+' || c == '.' || c == '-');
  }
  // dpkg's own place first: a test may run with a PATH that lacks the very tool it looks for.
  const std::string dpkg_query =
      ::access("/usr/bin/dpkg-query", X_OK) == 0 ? "/usr/bin/dpkg-query" : find_on_path("dpkg-query");
  std::string status;
  if (valid && !dpkg_query.empty()) {
    const std::string cmd = dpkg_query + " -W -f='${db:Status-Status}' " + package + " 2>/dev/null";
    const std::unique_ptr<FILE, int (*)(FILE*)> pipe(::popen(cmd.c_str(), "r"), ::pclose);
    if (pipe) {
      char buf[64];
      for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, pipe.get())) > 0;) status.append(buf, n);
    }
  }
  return cache[package] = (status == "installed");
}

enum class Verdict { kRun, kSkip, kFail };

struct Requirement {
  Verdict verdict = Verdict::kRun;
  std::string message;  // empty when kRun
};

// The decision of LOSMIMO_REQUIRE, given whether the package is installed.
inline Requirement requirement(bool present, bool package_installed, const std::string& package,
                               const std::string& what) {
  if (present) return {};
  if (!package_installed) {
    return {Verdict::kSkip, what + " is missing and Debian package " + package +
                                " is not installed (scripts/setup --tests installs it)"};
  }
  return {Verdict::kFail, what + " is missing although Debian package " + package +
                              " is installed: it should provide it (a wrong path, or a broken "
                              "install: apt-get install --reinstall " +
                              package + ")"};
}

inline Requirement require(bool present, const std::string& package, const std::string& what) {
  return requirement(present, present || debian_package_installed(package), package, what);
}

}  // namespace losmimo::test_support

#define LOSMIMO_REQUIRE(present, package, what)                                       \
  if (const ::losmimo::test_support::Requirement losmimo_requirement_ =               \
          ::losmimo::test_support::require((present), (package), (what));             \
      losmimo_requirement_.verdict == ::losmimo::test_support::Verdict::kRun) {       \
  } else if (losmimo_requirement_.verdict == ::losmimo::test_support::Verdict::kSkip) \
    GTEST_SKIP() << losmimo_requirement_.message;                                     \
  else                                                                                \
    FAIL() << losmimo_requirement_.message

#define LOSMIMO_REQUIRE_FILE(path, package) LOSMIMO_REQUIRE(std::filesystem::exists(path), (package), std::string(path))

#define LOSMIMO_REQUIRE_PROGRAM(name, package)                                     \
  LOSMIMO_REQUIRE(!::losmimo::test_support::find_on_path(name).empty(), (package), \
                  std::string("the program ") + (name) + " on PATH")

#define LOSMIMO_SKIP_MACHINE_DEPENDENT(reason) GTEST_SKIP() << ::losmimo::test_support::kMachineDependentTag << reason
