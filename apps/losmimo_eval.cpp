// losmimo-eval: link metrics (ICN, f, per-stream SINR, sum rates) of given UAV positions.
#include <CLI/CLI.hpp>
#include <iostream>

#include "losmimo/apps/lib/eval_app.h"
#include "losmimo/apps/lib/exit_codes.h"
#include "version_flag.h"

int main(int argc, char** argv) {
  losmimo::apps::EvalOptions options;
  CLI::App app{"Metrics of UAV positions in a LoS MIMO scenario (losmimo)"};
  losmimo::apps::add_version_flag(app);
  app.add_option("--positions", options.positions_path,
                 "CSV of UAV positions x,y,z [m], or a table of swarms such as losmimo-experiment's positions.csv")
      ->required();
  app.add_option("--select", options.selection,
                 "one swarm of a positions table: column=value (repeatable), e.g. --select algorithm=gd "
                 "--select trial=0");
  app.add_option("--config", options.config_path, "INI scenario (default: the paper's)");
  app.add_option("--set", options.overrides, "override a key: section.key=value (repeatable)");
  app.add_flag("--csv", options.csv, "machine-readable CSV output");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? losmimo::apps::kExitOk : losmimo::apps::kExitBadInput;
  }
  return losmimo::apps::run_eval_app(options, std::cout, std::cerr);
}
