#pragma once
// `losmimo-replay`: a rawlog's sensor stream through an estimator, offline (rawlog/replay.h).
// Messages go to `err` prefixed "losmimo-replay:", the summary to `out`.
//
// Exit code: 0 complete log replayed, 2 bad input (missing file, not a rawlog, bad
// option or CONFIG), 1 runtime error or truncated/corrupt log (its readable prefix replayed and
// written, the report says where and why reading stopped), 3 complete log of a run that was
// ended by a fault (losmimo-record's exit 3): every epoch up to the fault replayed and written,
// the status and the reason from END_OF_LOG go to `err`.
// Outputs (--out DIR) are written into DIR.partial/ and renamed into place with their manifest
// (common/staged_output.h); summary.csv's `complete` agrees with the exit code. A DIR that holds
// an earlier replay (or anything else) is refused with exit 2 before reading, unless `replace`.
#include <iosfwd>
#include <string>

namespace losmimo::apps {

struct ReplayAppOptions {
  std::string rawlog_path;
  std::string estimator;  // "", "ekf" or "pf"
  bool refine = false;
  bool no_refine = false;
  std::string out_dir;    // empty: summary to stdout only (unless out_given: then an error)
  bool strict = false;    // stop at classes the reader cannot bound, no sandbox (RawlogReaderOptions)
  bool replace = false;   // replace an earlier replay in out_dir
  bool out_given = false; // --out was given (so an empty out_dir is a mistake, not "none")
};
int run_replay_app(const ReplayAppOptions& options, std::ostream& out, std::ostream& err);


}  // namespace losmimo::apps
