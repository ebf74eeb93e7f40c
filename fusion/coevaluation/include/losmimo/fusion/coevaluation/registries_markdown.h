#pragma once
// The registries written out: docs/registries.md's generated tables (a test keeps the page equal
// to them) and losmimo-experiment's --help list.
#include <string>

namespace losmimo::coevaluation {

// Markdown: the planners (name, kind, sections, whether positions reach them, summary), the
// estimators (name, keys of their own, summary) and the row aliases, in registration order.
std::string registries_markdown();
// Plain text for --help: "planners: a, b, ...\nestimators: ...\nrows: alias = planner+estimator, ...".
std::string registries_help();

}  // namespace losmimo::coevaluation
