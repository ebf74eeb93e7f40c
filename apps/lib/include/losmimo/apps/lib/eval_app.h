#pragma once
// `losmimo-eval`: metrics of given UAV positions in a scenario.
// Output: a readable table, or with csv = true the lines
//   stream,sinr_nv_db,sinr_zf_db,sinr_mf_db      (one row per stream, 1-based)
//   icn,<v>  objective,<v>  sum_rate_nv_bps_hz,<v>  sum_rate_zf_bps_hz,<v>
// Returns the process exit code (exit_codes.h); on bad input the message on err names the file,
// line and field.
// Fewer UAVs than BS antennas is reported (ICN 0, ZF undefined), not an error.

#include <iosfwd>
#include <string>
#include <vector>

namespace losmimo::apps {

struct EvalOptions {
  std::string positions_path;
  std::string config_path;             // empty: the built-in paper scenario
  std::vector<std::string> overrides;  // "section.key=value"
  // "column=value": one swarm of a positions table (losmimo-experiment's positions.csv,
  // placement/positions_csv.h), e.g. {"sweep=sigma_loc_m", "value=0", "algorithm=gd", "trial=3",
  // "stage=final"}.
  std::vector<std::string> selection;
  bool csv = false;
};

int run_eval_app(const EvalOptions& options, std::ostream& out, std::ostream& err);

}  // namespace losmimo::apps
