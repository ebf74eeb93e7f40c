// track.png of a range-only replay (range_replay.h).
#include <filesystem>
#include <fstream>

#include "losmimo/placement/common/gnuplot.h"
#include "losmimo/fusion/rawlog/mrpt_logs/range_replay.h"
#include "track_figure_data.h"

namespace losmimo::mrpt_logs {

std::vector<std::string> write_range_plot(const RangeReplayResult& result, const localization::BeaconMap& beacons,
                                          const std::string& dir) {
  const std::filesystem::path d(dir);
  write_ellipses_dat(result.track, d / "ellipses.dat");
  write_map_dat(beacons, d / "beacons.dat");
  {
    std::ofstream f(d / "track.gp");
    f << "set terminal pngcairo size 900,800\nset output 'track.png'\nset datafile separator ','\n"
         "set size ratio -1\nset key outside bottom center horizontal\nset grid\n"
         "set xlabel 'x [m]'\nset ylabel 'y [m]'\n"
         "set title 'losmimo-replay ("
      << result.estimator << "): estimate, dead reckoning" << (result.truth_frames ? ", ground truth" : "")
      << ", beacons, 2-sigma ellipses'\n"
      << "plot 'track.csv' skip 1 using 3:4 with lines lw 2 lc rgb '#1f77b4' title 'estimate', \\\n"
         "     'track.csv' skip 1 using 16:17 with lines dt 2 lc rgb '#7f7f7f' title 'dead reckoning', \\\n";
    if (result.truth_frames) {
      f << "     'track.csv' skip 1 using 20:21 with lines lc rgb '#2ca02c' title 'ground truth', \\\n";
    }
    f << "     'ellipses.dat' using 1:2:3:4:5 with ellipses lc rgb '#d62728' "
         "title '2-sigma', \\\n"
         "     'beacons.dat' using 2:3 with points pt 5 ps 1.5 lc rgb 'black' "
         "title 'beacons', \\\n"
         "     '' using 2:3:1 with labels offset 1,1 notitle\n";
    if (!f) throw std::runtime_error((d / "track.gp").string() + ": write failed");
  }
  return common::render_gnuplot(dir, {"track"}, "track.gp (and its data) written, no track.png");
}

}  // namespace losmimo::mrpt_logs
