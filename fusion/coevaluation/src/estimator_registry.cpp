// The estimator registry, the rows' aliases and the co-evaluation's direct planner
// (estimator_registry.h).
#include "losmimo/fusion/coevaluation/estimator_registry.h"

#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <utility>

#include "losmimo/fusion/coevaluation/coevaluation.h"
#include "losmimo/placement/common/field_error.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/common/named_registry.h"
#include "losmimo/placement/common/text.h"
#include "losmimo/fusion/centralized.h"
#include "losmimo/placement/settings.h"
#include "trial_parts.h"

namespace losmimo::coevaluation {

namespace {

common::NamedRegistry<EstimatorEntry>& registry() {
  static common::NamedRegistry<EstimatorEntry> entries("estimator", builtin_estimators());
  return entries;
}

// Solutions of eq. 4 by (settings, start): the co-evaluation solves each start once, whichever
// sweep point asks first. The solve is deterministic, so a duplicate solve by a second thread
// changes nothing.
class CentralizedSolutions {
 public:
  placement::DirectSolution get(const placement::PlacementSettings& p, const Eigen::Matrix3Xd& start_m) {
    const std::string key = placement::to_ini(p) + "#start " +
                            std::string(reinterpret_cast<const char*>(start_m.data()),
                                        static_cast<std::size_t>(start_m.size()) * sizeof(double));
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      const auto it = solutions_.find(key);
      if (it != solutions_.end()) return it->second;
    }
    fusion::CentralizedConfig cc;
    cc.target_icn = p.run.target_icn;
    const fusion::CentralizedResult c = fusion::solve_centralized(p.scenario, start_m, cc);
    placement::DirectSolution solution{c.positions_m, c.status == fusion::CentralizedStatus::kFeasible};
    const std::lock_guard<std::mutex> lock(mutex_);
    if (solutions_.size() >= kMaxKept) solutions_.clear();  // a bound for long-lived processes
    return solutions_.emplace(key, std::move(solution)).first->second;
  }

 private:
  static constexpr std::size_t kMaxKept = 4096;
  std::mutex mutex_;
  std::map<std::string, placement::DirectSolution> solutions_;
};

}  // namespace

void register_estimator(EstimatorEntry entry) {
  if (!entry.run || !entry.refuses) {
    throw std::invalid_argument("register_estimator: " + entry.name + ": needs run and refuses");
  }
  registry().add(std::move(entry));
}

const EstimatorEntry* find_estimator(const std::string& name) { return registry().find(name); }
const EstimatorEntry& estimator_entry(const std::string& name) { return registry().at(name); }
std::vector<std::string> estimator_names() { return registry().names(); }

const std::vector<RowAlias>& row_aliases() {
  static const std::vector<RowAlias> aliases = {{"gd_gauss", "gd", "gauss"},
                                                {"gd_gauss_matched", "gd", "gauss_matched"},
                                                {"gd_gauss_shape_matched", "gd", "gauss_shape_matched"},
                                                {"gd_gauss_split_matched", "gd", "gauss_split_matched"},
                                                {"gd_ekf", "gd", "ekf"},
                                                {"gd_ekf_nofallback", "gd", "ekf_nofallback"},
                                                {"gd_pf", "gd", "pf"},
                                                {"gd_ekf_ceres", "gd", "ekf_ceres"},
                                                {"bf", "bf", "truth"},
                                                {"ura_ekf", "ura", "ekf"},
                                                {"centralized", "centralized", "truth"},
                                                {"cap_ekf", "cap", "ekf"}};
  return aliases;
}

std::vector<CoevalRow> aliased_rows(const std::vector<std::string>& aliases) {
  std::vector<CoevalRow> rows;
  for (const std::string& name : aliases) {
    const auto it =
        std::find_if(row_aliases().begin(), row_aliases().end(), [&](const RowAlias& a) { return a.alias == name; });
    if (it == row_aliases().end()) throw std::logic_error("aliased_rows: '" + name + "' is not an alias");
    rows.push_back({it->alias, it->planner, it->estimator});
  }
  return rows;
}

CoevalRow parse_row(const std::string& text, const std::string& where) {
  register_coevaluation_planners();
  for (const RowAlias& a : row_aliases()) {
    if (a.alias == text) return {a.alias, a.planner, a.estimator};
  }
  const std::size_t plus = text.find('+');
  if (plus != std::string::npos) {
    const std::string planner = common::trim(text.substr(0, plus));
    const std::string estimator = common::trim(text.substr(plus + 1));
    if (!placement::find_planner(planner)) {
      throw common::InputError(where + ": '" + text + "': unknown planner '" + planner +
                               "' (known: " + common::join(placement::planner_names()) + ")");
    }
    if (!find_estimator(estimator)) {
      throw common::InputError(where + ": '" + text + "': unknown estimator '" + estimator +
                               "' (known: " + common::join(estimator_names()) + ")");
    }
    return {planner + "+" + estimator, planner, estimator};
  }
  throw common::InputError(where + ": unknown algorithm '" + text +
                           "' (known: " + common::join_with(row_aliases(), [](const RowAlias& a) { return a.alias; }) +
                           "; or planner+estimator, planners: " + common::join(placement::planner_names()) +
                           ", estimators: " + common::join(estimator_names()) + ")");
}

void resolve_rows(std::vector<CoevalRow>& rows, placement::UraVariant ura_variant, const std::string& field) {
  const std::string ura = experiment::ura_algorithm_of(ura_variant).name();
  for (CoevalRow& row : rows) {
    if (row.name == "ura_ekf") row.planner = ura;
    // A pair that has an alias is named by it.
    for (const RowAlias& a : row_aliases()) {
      const std::string planner = a.alias == "ura_ekf" ? ura : a.planner;
      if (planner == row.planner && a.estimator == row.estimator) row.name = a.alias;
    }
    if (const std::optional<std::string> why =
            estimator_entry(row.estimator).refuses(placement::planner_entry(row.planner))) {
      throw common::FieldError(field, row.name + ": " + *why);
    }
  }
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (rows[i].same_pair(rows[j])) throw common::FieldError(field, "algorithm '" + rows[i].name + "' listed twice");
    }
  }
}

void register_coevaluation_planners() {
  static std::once_flag once;
  std::call_once(once, [] {
    auto solutions = std::make_shared<CentralizedSolutions>();
    placement::PlannerEntry e;
    e.name = "centralized";
    e.summary = "the Ceres solution of eq. 4 with perfect knowledge, flown straight (co-evaluation reference)";
    e.plot_color = "#17becf";
    e.solve = [solutions](const placement::PlacementSettings& p, const Eigen::Matrix3Xd& start_m) {
      return solutions->get(p, start_m);
    };
    placement::register_planner(std::move(e));
  });
}

experiment::TrialRecord CoevalTrial::record(const CoevalRow& row, const placement::RunResult& run) const {
  return experiment::make_record(settings, sweep, point, trial, row.name, run);
}

}  // namespace losmimo::coevaluation
