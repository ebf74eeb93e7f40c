// losmimo-replay: a rawlog's sensor stream through an estimator, offline (rawlog/replay.h).
// Exit codes: 0 complete log replayed, 1 runtime failure or truncated/corrupt log (its readable
// prefix replayed), 2 bad input, 3 complete log of a run that was ended by a fault (the status
// and the reason from the log are printed; everything up to the fault is replayed).
#include <sys/resource.h>

#include <CLI/CLI.hpp>
#include <iostream>

#include "losmimo/apps/replay_app.h"

int main(int argc, char** argv) {
  losmimo::apps::ReplayAppOptions options;
  CLI::App app{"Replay a rawlog through an estimator and evaluate the placement along it"};
  app.add_option("rawlog", options.rawlog_path, "input rawlog (gzip or plain)")->required();
  app.add_option("--estimator", options.estimator, "ekf or pf (default: as recorded)");
  app.add_flag("--refine", options.refine, "Ceres sliding-window refinement (default: as recorded)");
  app.add_flag("--no-refine", options.no_refine, "no refinement");
  app.add_option("--out", options.out_dir, "write estimates.csv, epochs.csv, summary.csv here");
  app.add_flag("--strict", options.strict, "stop at object classes the reader cannot bound");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
#if !defined(__SANITIZE_ADDRESS__)
  // Backstop for foreign classes MRPT parses unchecked: a corrupted length then fails with
  // bad_alloc (reported) instead of taking the machine's memory.
  const rlim_t kAddressSpace = rlim_t{8} << 30;
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) == 0 && (limit.rlim_cur == RLIM_INFINITY || limit.rlim_cur > kAddressSpace)) {
    limit.rlim_cur = kAddressSpace;
    setrlimit(RLIMIT_AS, &limit);
  }
#endif
  return losmimo::apps::run_replay_app(options, std::cout, std::cerr);
}
