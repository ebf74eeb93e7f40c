// losmimo-experiment: Monte Carlo reproduction of the paper's Figs 1-3 (see README).
#include <CLI/CLI.hpp>
#include <iostream>

#include "losmimo/fusion/experiment_extensions.h"
#include "losmimo/placement/experiment.h"

int main(int argc, char** argv) {
  losmimo::placement::ExperimentOptions options;
  CLI::App app{"Monte Carlo placement experiments: the paper's Figs 1-3 (losmimo)"};
  app.add_option("--config", options.config_path, "INI config (default: the paper's setup, quick trial count)");
  app.add_option("--set", options.overrides, "override a key: section.key=value (repeatable)");
  app.add_option("--out", options.out_dir, "output directory")->capture_default_str();
  app.add_option("--trials", options.trials, "random starts per sweep point (paper: 500)")->check(CLI::PositiveNumber);
  app.add_option("--threads", options.threads, "worker threads (0: all cores); results do not depend on it")
      ->check(CLI::NonNegativeNumber);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  return losmimo::placement::run_experiment_app(options, losmimo::fusion::experiment_extensions(), std::cout, std::cerr);
}
