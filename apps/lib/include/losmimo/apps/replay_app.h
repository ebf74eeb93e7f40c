#pragma once
// `losmimo-replay`: a rawlog's sensor stream through an estimator, offline (rawlog/replay.h).
// Messages go to `err` prefixed "losmimo-replay:", the summary to `out`.
//
// Exit code: 0 complete log replayed, 2 bad input (missing file, not a rawlog, bad
// option or CONFIG), 1 runtime error or truncated/corrupt log (its readable prefix replayed and
// written, the report says where and why reading stopped), 3 complete log of a run that was
// ended by a fault (losmimo-record's exit 3): every epoch up to the fault replayed and written,
// the status and the reason from END_OF_LOG go to `err`.
#include <iosfwd>
#include <string>

namespace losmimo::apps {

struct ReplayAppOptions {
  std::string rawlog_path;
  std::string estimator;  // "", "ekf" or "pf"
  bool refine = false;
  bool no_refine = false;
  std::string out_dir;    // empty: summary to stdout only
  bool strict = false;    // stop at classes the reader cannot bound (RawlogReaderOptions)
};
int run_replay_app(const ReplayAppOptions& options, std::ostream& out, std::ostream& err);


}  // namespace losmimo::apps
