// docs/registries.md's tables are the registries written out: this test fails when an entry is
// added, removed or changed without the page. To rewrite the page's generated part:
//   LOSMIMO_WRITE_REGISTRIES=1 build/tests/coevaluation/coevaluation_tests --gtest_filter='Registries.DocsPage*'
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "losmimo/fusion/coevaluation/estimator_registry.h"
#include "losmimo/fusion/coevaluation/registries_markdown.h"
#include "losmimo/placement/planner_registry.h"
#include "support/files.h"

namespace losmimo::coevaluation {
namespace {

TEST(Registries, DocsPage_ListsEveryRegisteredEntry) {
  const std::string path = std::string(LOSMIMO_SOURCE_DIR) + "/docs/registries.md";
  const std::string page = test_support::read_file(path);
  const std::string begin = "<!-- generated: registries_markdown() -->\n";
  const std::string end = "<!-- end generated -->\n";
  const std::size_t a = page.find(begin), b = page.find(end);
  ASSERT_NE(a, std::string::npos) << path << " has no generated part";
  ASSERT_NE(b, std::string::npos) << path << " has no end of its generated part";
  const std::string generated = registries_markdown();
  if (std::getenv("LOSMIMO_WRITE_REGISTRIES")) {
    std::ofstream(path, std::ios::binary) << page.substr(0, a + begin.size()) + generated + page.substr(b);
    return;
  }
  EXPECT_EQ(page.substr(a + begin.size(), b - a - begin.size()), generated)
      << "docs/registries.md is out of date: rewrite it with LOSMIMO_WRITE_REGISTRIES=1 (see the test's header)";
  // Every registered name has a row (the builtin ones: this process registers no test entry).
  for (const std::string& name : placement::planner_names()) {
    EXPECT_NE(generated.find("| `" + name + "` |"), std::string::npos) << name;
  }
  for (const std::string& name : estimator_names()) {
    EXPECT_NE(generated.find("| `" + name + "` |"), std::string::npos) << name;
  }
}

TEST(Registries, Help_NamesEveryPlannerEstimatorAndAlias) {
  const std::string help = registries_help();
  for (const std::string& name : placement::planner_names()) EXPECT_NE(help.find(name), std::string::npos) << name;
  for (const std::string& name : estimator_names()) EXPECT_NE(help.find(name), std::string::npos) << name;
  for (const RowAlias& a : row_aliases()) {
    EXPECT_NE(help.find(a.alias + " = " + a.planner + "+" + a.estimator), std::string::npos) << a.alias;
  }
}

}  // namespace
}  // namespace losmimo::coevaluation
