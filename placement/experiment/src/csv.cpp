#include "losmimo/placement/experiment/csv.h"

#include <cmath>
#include <cstdio>
#include <ostream>

#include "losmimo/placement/common/format.h"
#include "losmimo/placement/experiment/metrics.h"

namespace losmimo::experiment {

namespace {
// Positions must read back exactly, for recomputation.
}  // namespace

void write_trials_header(std::ostream& out, const std::vector<std::string>& extra) {
  out << "sweep,value,algorithm,trial,seed";
  for (const Metric& m : kMetrics) out << "," << m.name;
  out << ",start_seed,status";
  for (const std::string& e : extra) out << "," << e;
  out << "\n";
}

void write_trials_rows(std::ostream& out, const std::vector<TrialRecord>& records, std::size_t num_extra) {
  for (const TrialRecord& r : records) {
    out << r.sweep << "," << common::format_csv(r.value) << "," << r.algorithm << "," << r.trial << "," << r.seed;
    for (const Metric& m : kMetrics) {
      out << ",";
      if (m.is_real()) {
        out << common::format_csv(m.get(r));
      } else {
        out << static_cast<long long>(m.get(r));
      }
    }
    out << "," << r.start_seed << "," << r.status;
    for (std::size_t i = 0; i < num_extra; ++i)
      out << "," << common::format_csv(i < r.extra.size() ? r.extra[i] : std::nan(""));
    out << "\n";
  }
}

void write_positions_header(std::ostream& out) { out << "sweep,value,algorithm,trial,uav,stage,x,y,z\n"; }

void write_positions_rows(std::ostream& out, const std::vector<TrialRecord>& records) {
  for (const TrialRecord& r : records) {
    const std::string prefix =
        r.sweep + "," + common::format_csv(r.value) + "," + r.algorithm + "," + std::to_string(r.trial) + ",";
    for (const auto& [stage, q] :
         {std::pair<const char*, const Eigen::Matrix3Xd*>{"start", &r.start_m}, {"final", &r.final_m}}) {
      for (Eigen::Index n = 0; n < q->cols(); ++n) {
        out << prefix << n + 1 << "," << stage << "," << common::format_exact((*q)(0, n)) << ","
            << common::format_exact((*q)(1, n)) << "," << common::format_exact((*q)(2, n)) << "\n";
      }
    }
  }
}

void write_traces_csv(std::ostream& out, const std::vector<TracedRun>& traces) {
  out << "algorithm,trial,iteration,icn,objective,sinr_nv_db,sinr_zf_db,sinr_mf_db,placement_dist_m,probe_dist_m\n";
  for (const TracedRun& t : traces) {
    if (!t.fig1()) continue;  // the path figure's runs under error: paths.csv only
    for (const placement::IterationRecord& r : t.result.trace) {
      out << to_string(t.algorithm) << "," << t.trial << "," << r.iteration << "," << common::format_csv(r.icn) << ","
          << common::format_csv(r.objective) << "," << common::format_csv(r.sinr_nv_db) << ","
          << common::format_csv(r.sinr_zf_db) << "," << common::format_csv(r.sinr_mf_db) << ","
          << common::format_csv(r.placement_dist_m) << "," << common::format_csv(r.probe_dist_m) << "\n";
    }
  }
}

}  // namespace losmimo::experiment
