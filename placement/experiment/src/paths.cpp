#include "losmimo/placement/experiment/paths.h"

#include <cmath>
#include <filesystem>
#include <ostream>
#include <sstream>

#include "losmimo/placement/common/atomic_file.h"
#include "losmimo/placement/common/format.h"
#include "losmimo/placement/ura.h"

namespace losmimo::experiment {

namespace {
// 8 significant digits: 0.01 mm at 1 km, enough for a figure.
std::string pos(double v) { return common::format_g(v, 8); }

std::string run_title(const TracedRun& t) {
  std::string name = t.algorithm == Algorithm::kGd   ? "GD"
                     : t.algorithm == Algorithm::kBf ? "BF"
                                                     : to_string(t.algorithm);
  return name + (t.fig1() ? ", no error" : ", sigma_{act} " + common::format_double(t.sigma_act_m) + " m");
}
}  // namespace

std::vector<const TracedRun*> runs_with_path(const std::vector<TracedRun>& traces) {
  std::vector<const TracedRun*> runs;
  for (const TracedRun& t : traces) {
    if (!t.result.path.empty()) runs.push_back(&t);
  }
  return runs;
}

void write_paths_csv(std::ostream& out, const std::vector<TracedRun>& traces) {
  out << "algorithm,sigma_act_m,trial,iteration,uav,x,y,z\n";
  for (const TracedRun* t : runs_with_path(traces)) {
    const std::string prefix =
        to_string(t->algorithm) + "," + common::format_double(t->sigma_act_m) + "," + std::to_string(t->trial) + ",";
    for (std::size_t i = 0; i < t->result.path.size(); ++i) {
      const Eigen::Matrix3Xd& q = t->result.path[i];
      for (Eigen::Index m = 0; m < q.cols(); ++m) {
        out << prefix << t->result.trace[i].iteration << "," << m + 1 << "," << pos(q(0, m)) << "," << pos(q(1, m))
            << "," << pos(q(2, m)) << "\n";
      }
    }
  }
}

namespace {

// paths.dat: index i < n: run i's paths, one block per UAV ("x y z uav"); index n + i: its
// starts and ends ("x y z uav stage fy fz", stage 0 start, 1 end; fy, fz the lateral position
// folded into one lateral period, below); index 2n: the rigid URA slots.
//
// The fold: orthogonality depends on each UAV's direction from the BS only modulo the lateral
// period lambda / d_t (in direction cosines; lambda x / d_t = 20 m at 1 km on the paper's
// setup), so GD and BF end on lattice-equivalent points anywhere in the cube. Folding every
// direction into one period around the boresight and drawing it at the cube centre's depth
// shows the URA's grid (up to a common shift, which changes no ICN).
std::string paths_dat(const ExperimentSettings& s, const std::vector<const TracedRun*>& runs) {
  std::ostringstream dat;
  const placement::Scenario& sc = s.placement.scenario;
  const double depth_m = sc.cube_center_m.x();
  const double period = sc.wavelength_m() / sc.bs_spacing_m;  // in direction cosines
  const auto fold = [&](double lateral_m, double x_m, double center_m) {
    const double u = lateral_m / x_m - center_m / depth_m;
    return depth_m * (u - period * std::round(u / period));
  };
  for (const TracedRun* t : runs) {
    const std::vector<Eigen::Matrix3Xd>& path = t->result.path;
    dat << "# " << to_string(t->algorithm) << " sigma_act " << t->sigma_act_m << ": x y z uav\n";
    for (Eigen::Index m = 0; m < path.front().cols(); ++m) {
      for (const Eigen::Matrix3Xd& q : path)
        dat << pos(q(0, m)) << " " << pos(q(1, m)) << " " << pos(q(2, m)) << " " << m + 1 << "\n";
      dat << "\n";
    }
    dat << "\n";
  }
  for (const TracedRun* t : runs) {
    dat << "# " << to_string(t->algorithm) << ": start and end, x y z uav stage folded_y folded_z\n";
    for (const auto& [stage, q] :
         {std::pair<int, const Eigen::Matrix3Xd*>{0, &t->result.path.front()}, {1, &t->result.path.back()}}) {
      for (Eigen::Index m = 0; m < q->cols(); ++m) {
        dat << pos((*q)(0, m)) << " " << pos((*q)(1, m)) << " " << pos((*q)(2, m)) << " " << m + 1 << " " << stage
            << " " << pos(fold((*q)(1, m), (*q)(0, m), sc.cube_center_m.y())) << " "
            << pos(fold((*q)(2, m), (*q)(0, m), sc.cube_center_m.z())) << "\n";
      }
    }
    dat << "\n\n";
  }
  dat << "# rigid URA slots (spacing multiple " << s.placement.ura.spacing_multiple << "): x y z\n";
  if (sc.num_uavs == sc.num_bs_antennas()) {
    const Eigen::Matrix3Xd slots = placement::optimal_ura_positions_m(sc, s.placement.ura.spacing_multiple);
    for (Eigen::Index k = 0; k < slots.cols(); ++k)
      dat << pos(slots(0, k)) << " " << pos(slots(1, k)) << " " << pos(slots(2, k)) << "\n";
  } else {
    dat << "nan nan nan\n";
  }
  return dat.str();
}

// paths.gp: per run a lateral view, a side view and the folded directions (rows of the multiplot).
std::string paths_gp(const ExperimentSettings& s, const std::vector<const TracedRun*>& runs) {
  const std::size_t n = runs.size();
  const placement::Scenario& sc = s.placement.scenario;
  const double depth_m = sc.cube_center_m.x();
  const double period = sc.wavelength_m() / sc.bs_spacing_m;  // in direction cosines
  std::ostringstream gp;
  gp << "set terminal pngcairo size " << 520 * n << ",1560 enhanced font 'Sans,10'\n"
     << "set output 'paths.png'\nset datafile missing 'nan'\nset size ratio -1\nset grid\nunset key\n"
     << "set palette defined (0 '#1f77b4', 1 '#2ca02c', 2 '#ff7f0e', 3 '#d62728', 4 '#9467bd')\n"
     << "set cbrange [1:" << sc.num_uavs << "]\nunset colorbox\n"
     << "set multiplot layout 3," << n
     << " title 'UAV paths, start (open circle) to end (filled); BF probe flights not drawn'\n";
  for (std::size_t i = 0; i < n; ++i) {
    gp << "set title '" << run_title(*runs[i]) << ": lateral view (from the BS, + = boresight)'\n"
       << "set xlabel 'y [m]'\nset ylabel 'z [m]'\nunset arrow\nunset label\n"
       << "set label 1 '+' at " << pos(sc.cube_center_m.y()) << "," << pos(sc.cube_center_m.z()) << " center front\n"
       << "plot 'paths.dat' index " << i << " using 2:3:4 with lines lw 1 lc palette, '' index " << n + i
       << " using 2:($5 == 0 ? $3 : 1/0):4 with points pt 6 ps 1.2 lc palette, '' index " << n + i
       << " using 2:($5 == 1 ? $3 : 1/0):4 with points pt 7 ps 1.2 lc palette, '' index " << 2 * n
       << " using 2:3 with points pt 2 ps 1.5 lc rgb '#7f7f7f'\n";
  }
  for (std::size_t i = 0; i < n; ++i) {
    gp << "set title '" << run_title(*runs[i]) << ": side view'\n"
       << "set xlabel 'x [m], along the link'\nset ylabel 'z [m]'\nunset label\nunset arrow\n"
       << "set arrow 1 from graph 0.25, graph 0.93 to graph 0.03, graph 0.93 lw 2 front\n"
       << "set label 2 'to the BS (x = 0)' at graph 0.04, graph 0.97 front\n"
       << "plot 'paths.dat' index " << i << " using 1:3:4 with lines lw 1 lc palette, '' index " << n + i
       << " using 1:($5 == 0 ? $3 : 1/0):4 with points pt 6 ps 1.2 lc palette, '' index " << n + i
       << " using 1:($5 == 1 ? $3 : 1/0):4 with points pt 7 ps 1.2 lc palette\n";
  }
  const double half = 0.5 * period * depth_m;
  for (std::size_t i = 0; i < n; ++i) {
    gp << "set title '" << run_title(*runs[i]) << ": directions folded into one lateral period'\n"
       << "set xlabel 'y folded [m] at x = " << common::format_double(depth_m) << " m'\nset ylabel 'z folded [m]'\n"
       << "unset label\nunset arrow\nset xrange [" << pos(-half) << ":" << pos(half) << "]\nset yrange [" << pos(-half)
       << ":" << pos(half) << "]\n"
       << "plot 'paths.dat' index " << n + i
       << " using 6:($5 == 0 ? $7 : 1/0):4 with points pt 6 ps 1 lc palette, '' index " << n + i
       << " using 6:($5 == 1 ? $7 : 1/0):4 with points pt 7 ps 1.6 lc palette\n";
  }
  gp << "unset multiplot\n";
  return gp.str();
}

}  // namespace

std::string write_path_figure(const ExperimentSettings& s, const std::vector<TracedRun>& traces,
                              const std::string& dir) {
  const std::vector<const TracedRun*> runs = runs_with_path(traces);
  if (runs.empty()) return "";
  namespace fs = std::filesystem;
  common::write_stream_atomically((fs::path(dir) / "paths.csv").string(),
                                  [&](std::ostream& o) { write_paths_csv(o, traces); });
  common::write_file_atomically((fs::path(dir) / "paths.dat").string(), paths_dat(s, runs));
  common::write_file_atomically((fs::path(dir) / "paths.gp").string(), paths_gp(s, runs));
  return "paths";
}

}  // namespace losmimo::experiment
