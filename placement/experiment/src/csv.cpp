#include "losmimo/experiment/csv.h"

#include <cmath>
#include <cstdio>
#include <ostream>

#include "losmimo/common/format.h"
#include "losmimo/experiment/metrics.h"

namespace losmimo::experiment {

namespace {
std::string fmt(double v) { return common::format_g(v, common::kCsvDigits); }
// Positions must read back exactly, for recomputation.
std::string exact(double v) { return common::format_g(v, common::kExactDigits); }
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
    out << r.sweep << "," << fmt(r.value) << "," << r.algorithm << "," << r.trial << "," << r.seed;
    for (const Metric& m : kMetrics) {
      out << ",";
      if (m.is_real()) {
        out << fmt(m.get(r));
      } else {
        out << static_cast<long long>(m.get(r));
      }
    }
    out << "," << r.start_seed << "," << r.status;
    for (std::size_t i = 0; i < num_extra; ++i) out << "," << fmt(i < r.extra.size() ? r.extra[i] : std::nan(""));
    out << "\n";
  }
}

void write_positions_header(std::ostream& out) { out << "sweep,value,algorithm,trial,uav,stage,x,y,z\n"; }

void write_positions_rows(std::ostream& out, const std::vector<TrialRecord>& records) {
  for (const TrialRecord& r : records) {
    const std::string prefix = r.sweep + "," + fmt(r.value) + "," + r.algorithm + "," +
                               std::to_string(r.trial) + ",";
    for (const auto& [stage, q] : {std::pair<const char*, const Eigen::Matrix3Xd*>{"start", &r.start_m},
                                   {"final", &r.final_m}}) {
      for (Eigen::Index n = 0; n < q->cols(); ++n) {
        out << prefix << n + 1 << "," << stage << "," << exact((*q)(0, n)) << "," << exact((*q)(1, n)) << ","
            << exact((*q)(2, n)) << "\n";
      }
    }
  }
}

void write_traces_csv(std::ostream& out, const std::vector<TracedRun>& traces) {
  out << "algorithm,trial,iteration,icn,objective,sinr_nv_db,sinr_zf_db,sinr_mf_db,placement_dist_m,probe_dist_m\n";
  for (const TracedRun& t : traces) {
    for (const placement::IterationRecord& r : t.result.trace) {
      out << to_string(t.algorithm) << "," << t.trial << "," << r.iteration << "," << fmt(r.icn) << ","
          << fmt(r.objective) << "," << fmt(r.sinr_nv_db) << "," << fmt(r.sinr_zf_db) << ","
          << fmt(r.sinr_mf_db) << "," << fmt(r.placement_dist_m) << "," << fmt(r.probe_dist_m) << "\n";
    }
  }
}

}  // namespace losmimo::experiment
