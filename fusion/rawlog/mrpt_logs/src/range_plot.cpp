// track.png of a range-only replay (range_replay.h).
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "losmimo/common/gnuplot.h"
#include "losmimo/mrpt_logs/range_replay.h"

namespace losmimo::mrpt_logs {

std::vector<std::string> write_range_plot(const RangeReplayResult& result, const localization::BeaconMap& beacons,
                                          const std::string& dir) {
  const std::filesystem::path d(dir);
  {
    // 2-sigma ellipses of the (x, y) block: gnuplot's "with ellipses" takes the full axes
    // (diameters) and the major axis' angle in degrees.
    std::ofstream f(d / "ellipses.dat");
    const std::size_t every = std::max<std::size_t>(1, result.track.size() / 20);
    for (std::size_t k = 0; k < result.track.size(); k += every) {
      const auto& b = result.track[k].belief;
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(b.cov.topLeftCorner<2, 2>());
      const Eigen::Vector2d l = es.eigenvalues().cwiseMax(0.0);
      const Eigen::Vector2d major = es.eigenvectors().col(1);
      f << b.mean(0) << "," << b.mean(1) << "," << 4.0 * std::sqrt(l(1)) << "," << 4.0 * std::sqrt(l(0)) << ","
        << std::atan2(major(1), major(0)) * 180.0 / 3.14159265358979323846 << "\n";
    }
    if (!f) throw std::runtime_error((d / "ellipses.dat").string() + ": write failed");
  }
  {
    std::ofstream f(d / "beacons.dat");
    for (const auto& [id, p] : beacons.beacons()) f << id << "," << p.x() << "," << p.y() << "," << p.z() << "\n";
    if (!f) throw std::runtime_error((d / "beacons.dat").string() + ": write failed");
  }
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
