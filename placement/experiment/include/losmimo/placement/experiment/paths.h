#pragma once
// The path figure: where the UAVs fly, from the random start to the final positions.
//   paths.csv  algorithm,sigma_act_m,trial,iteration,uav,x,y,z: the true positions after every
//              iteration of the runs that recorded them (TracedRun with a path: the Fig 1 runs
//              of trial 0, and GD and BF under the largest sigma_act), metres in the BS frame
//              (x along the link from the BS at the origin)
//   paths.png  per run two panels: the lateral view (y-z, as seen from the BS, with the
//              rigid URA's slots for scale) and the side view (x-z, the BS off to the left at
//              x = 0, marked with an arrow); one line per UAV, an open circle at its start, a
//              filled one at its end; and the start and end directions folded into one lateral
//              period (paths.cpp), where the end positions show the URA's grid. Only kept moves
//              are positions after an iteration: BF's probe flights are not drawn.
// paths.dat and paths.gp sit beside it.

#include <iosfwd>
#include <string>
#include <vector>

#include "losmimo/placement/experiment/engine.h"

namespace losmimo::experiment {

// The traced runs with a recorded path, in order.
std::vector<const TracedRun*> runs_with_path(const std::vector<TracedRun>& traces);

void write_paths_csv(std::ostream& out, const std::vector<TracedRun>& traces);

// Writes paths.csv, paths.dat and paths.gp into `dir` when a run has a path; returns the stem
// to render ("paths") or "" when there is none.
std::string write_path_figure(const ExperimentSettings& settings, const std::vector<TracedRun>& traces,
                              const std::string& dir);

}  // namespace losmimo::experiment
