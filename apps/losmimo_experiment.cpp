// losmimo-experiment: Monte Carlo reproduction of the paper's Figs 1-3 (docs/experiment.md).
//   losmimo-experiment [--config ...] [--set ...] [--out DIR]      everything, one process
//   losmimo-experiment --shard i/N --out DIR_i ...                 one slice of the jobs
//   losmimo-experiment merge DIR_0 ... DIR_N-1 --out DIR           shards -> one result
//   losmimo-experiment --resume DIR ...                            continue an interrupted run
// Every output folder is written in DIR.partial/ and renamed into place when complete; a folder
// that already holds results is refused unless --replace (docs/reliability.md).
//   mpirun -np K losmimo-experiment ...                            K ranks, rank 0 writes
#include <CLI/CLI.hpp>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#ifdef LOSMIMO_WITH_MPI
#include <mpi.h>
#endif

#include "losmimo/apps/lib/exit_codes.h"
#include "losmimo/apps/lib/experiment_app.h"
#include "losmimo/apps/lib/interrupt.h"
#include "losmimo/apps/lib/experiment_scene.h"
#include "losmimo/fusion/coevaluation/extensions.h"
#include "losmimo/fusion/coevaluation/registries_markdown.h"
#include "losmimo/placement/experiment/channel_sweeps.h"
#include "losmimo/placement/experiment/num_uavs_sweep.h"
#include "version_flag.h"

namespace {

#ifdef LOSMIMO_WITH_MPI
// Launched by mpirun (Open MPI or PMIx set these): only then is MPI initialised, so a plain
// run never pays for it.
bool launched_by_mpirun() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr ||
         std::getenv("PMI_RANK") != nullptr;
}

// Rank 0 receives every rank's text (MPI_Gatherv of the byte counts, then of the bytes).
std::vector<std::string> mpi_gather(const std::string& mine, int rank, int size) {
  const int length = static_cast<int>(mine.size());
  std::vector<int> lengths(rank == 0 ? size : 0);
  MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::vector<int> offsets(lengths.size());
  long long total = 0;
  for (std::size_t r = 0; r < lengths.size(); ++r) {
    offsets[r] = static_cast<int>(total);
    total += lengths[r];
  }
  std::string all(static_cast<std::size_t>(total), '\0');
  MPI_Gatherv(mine.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0, MPI_COMM_WORLD);
  std::vector<std::string> parts;
  for (std::size_t r = 0; r < lengths.size(); ++r) parts.push_back(all.substr(offsets[r], lengths[r]));
  return parts;
}
#endif

}  // namespace

int main(int argc, char** argv) {
  losmimo::apps::ExperimentOptions options;
  std::string out_dir = "results", shard, resume_dir;
  CLI::App app{"Monte Carlo placement experiments: the paper's Figs 1-3 (losmimo)"};
  losmimo::apps::add_version_flag(app);
  app.add_option("--config", options.config_path, "INI config (default: the paper's setup, quick trial count)");
  app.add_option("--set", options.overrides, "override a key: section.key=value (repeatable)");
  CLI::Option* out_option = app.add_option("--out", out_dir, "output directory")->capture_default_str();
  // Integer ranges: CLI11's PositiveNumber / NonNegativeNumber print their bounds as doubles
  // ("not in range 0.000000 to 1797...").
  constexpr int kMaxCount = std::numeric_limits<int>::max();
  app.add_option("--trials", options.trials, "random starts per sweep point (paper: 500)")
      ->check(CLI::Range(1, kMaxCount));
  app.add_option("--threads", options.threads, "worker threads (0: all cores); results do not depend on it")
      ->check(CLI::Range(0, kMaxCount));
  CLI::Option* shard_option =
      app.add_option("--shard", shard, "i/N: run only jobs j with j % N == i (0 <= i < N) into --out, for `merge`");
  CLI::Option* resume_option =
      app.add_option("--resume", resume_dir,
                     "continue the interrupted run of this output folder (same config; finished points are kept)");
  app.add_flag("--replace", options.replace,
               "replace the results already in the output folder (default: refuse, exit 2)");
  app.add_flag("--scene", options.scene,
               "also write paths.3Dscene (the path runs and the BS array, for MRPT's SceneViewer3D) beside paths.png");
  options.scene_writer = losmimo::apps::write_experiment_scene;
  // From the registries ([experiment] algorithms, [coevaluation] algorithms; docs/registries.md).
  app.footer("\n" + losmimo::coevaluation::registries_help());

  losmimo::apps::MergeOptions merge_options;
  CLI::App* merge = app.add_subcommand("merge", "merge the folders of shards 0..N-1 into one result");
  merge->add_option("dirs", merge_options.shard_dirs, "shard folders (written with --shard i/N)")->required();
  merge->add_option("--out", merge_options.out_dir, "output directory")->capture_default_str();
  merge->add_flag("--replace", merge_options.replace, "replace the results already in the output folder");
  merge->add_flag("--scene", merge_options.scene, "also write paths.3Dscene (as without merge)");
  merge_options.scene_writer = losmimo::apps::write_experiment_scene;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? losmimo::apps::kExitOk : losmimo::apps::kExitBadInput;
  }
  // Given (even as ''), or not: an empty value is refused, not taken as "not given".
  if (out_option->count() > 0) options.out_dir = out_dir;
  if (shard_option->count() > 0) options.shard = shard;
  if (resume_option->count() > 0) options.resume_dir = resume_dir;
  losmimo::experiment::ExperimentExtensions extensions = losmimo::coevaluation::experiment_extensions();
  for (auto& e : losmimo::experiment::channel_sweep_extensions()) extensions.push_back(std::move(e));
  extensions.push_back(losmimo::experiment::num_uavs_extension());
  if (merge->parsed()) {
    if (options.scene) {  // given before `merge`: the run's flag, not the merge's
      std::cerr << "losmimo-experiment: --scene: give it after `merge` (merge ... --scene)\n";
      return losmimo::apps::kExitBadInput;
    }
    return losmimo::apps::merge_experiment_app(merge_options, extensions, std::cout, std::cerr);
  }

#ifdef LOSMIMO_WITH_MPI
  if (launched_by_mpirun()) {
    MPI_Init(&argc, &argv);
    losmimo::apps::ExperimentCollective collective;
    MPI_Comm_rank(MPI_COMM_WORLD, &collective.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &collective.size);
    collective.gather = [&](const std::string& mine) { return mpi_gather(mine, collective.rank, collective.size); };
    options.collective = &collective;
    const int code = losmimo::apps::run_experiment_app(options, extensions, std::cout, std::cerr);
    // Every rank returns the same code for bad input; rank 0 reports a failure of any rank.
    int worst = code;
    MPI_Allreduce(&code, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    MPI_Finalize();
    return collective.rank == 0 ? worst : code;
  }
#endif
  // Ctrl-C: say where the finished trials are and how to continue (exit 130).
  losmimo::apps::install_interrupt_message(losmimo::apps::experiment_interrupt_message(
      std::vector<std::string>(argv, argv + argc),
      options.resume_dir ? *options.resume_dir : options.out_dir.value_or("results")));
  return losmimo::apps::run_experiment_app(options, extensions, std::cout, std::cerr);
}
