#include "losmimo/fusion/coevaluation/registries_markdown.h"

#include <string>
#include <vector>

#include "losmimo/fusion/coevaluation/estimator_registry.h"
#include "losmimo/placement/common/text.h"
#include "losmimo/placement/planner_registry.h"

namespace losmimo::coevaluation {

namespace {
std::string quoted(const std::vector<std::string>& items, const std::string& open, const std::string& close) {
  return common::join_with(items, [&](const std::string& i) { return open + i + close; });
}
}  // namespace

std::string registries_markdown() {
  register_coevaluation_planners();
  std::string md =
      "### Planners\n\n| name | kind | its own sections | positions reach it | what |\n|---|---|---|---|---|\n";
  for (const std::string& name : placement::planner_names()) {
    const placement::PlannerEntry& e = placement::planner_entry(name);
    md += "| `" + name + "` | " + (e.direct() ? "direct" : "iterative") + " | " + quoted(e.sections, "`[", "]`") +
          " | " + (e.uses_positions && !e.direct() ? "yes" : "no") + " | " + e.summary + " |\n";
  }
  md += "\n### Estimators\n\n| name | its own keys | what |\n|---|---|---|\n";
  for (const std::string& name : estimator_names()) {
    const EstimatorEntry& e = estimator_entry(name);
    md += "| `" + name + "` | " + quoted(e.keys, "`", "`") + " | " + e.summary + " |\n";
  }
  md += "\n### Row aliases\n\n| row | planner | estimator |\n|---|---|---|\n";
  for (const RowAlias& a : row_aliases()) {
    md += "| `" + a.alias + "` | `" + (a.alias == "ura_ekf" ? "ura` (`[coevaluation] ura_variant`)" : a.planner + "`") +
          " | `" + a.estimator + "` |\n";
  }
  return md;
}

std::string registries_help() {
  register_coevaluation_planners();
  const std::string rows = common::join_with(
      row_aliases(), [](const RowAlias& a) { return a.alias + " = " + a.planner + "+" + a.estimator; });
  return "planners: " + common::join(placement::planner_names()) + "\nestimators: " + common::join(estimator_names()) +
         "\nco-evaluation rows ([coevaluation] algorithms): planner+estimator, or " + rows + "\n";
}

}  // namespace losmimo::coevaluation
