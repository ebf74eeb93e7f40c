// track.csv, summary rows and track.png of a bearing-range replay (bearing_replay.h).
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/gnuplot.h"
#include "losmimo/fusion/rawlog/mrpt_logs/bearing_replay.h"
#include "losmimo/fusion/rawlog/mrpt_logs/range_log.h"
#include "track_figure_data.h"

namespace losmimo::mrpt_logs {

namespace {

using common::format_csv;

void pose_fields(std::ostream& f, const localization::Pose6& p) {
  for (int i = 0; i < 6; ++i) f << "," << format_csv(p(i));
}

}  // namespace

void write_bearing_track_csv(const BearingReplayResult& result, const std::string& path) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot write");
  f << "step,timestamp_s,x_m,y_m,z_m,yaw_rad,pitch_rad,roll_rad,var_x_m2,var_y_m2,var_z_m2,var_yaw_rad2,"
       "var_pitch_rad2,var_roll_rad2,readings,fused,nis,dr_x_m,dr_y_m,dr_z_m,dr_yaw_rad,dr_pitch_rad,dr_roll_rad,"
       "gt_x_m,gt_y_m,gt_z_m,gt_yaw_rad,gt_pitch_rad,gt_roll_rad,error_m,error_xy_m,yaw_error_rad,dr_error_m";
  if (result.refined)
    f << ",refined_x_m,refined_y_m,refined_z_m,refined_yaw_rad,refined_pitch_rad,refined_roll_rad,refined_error_m";
  f << "\n";
  for (const BearingTrackRow& r : result.track) {
    f << r.step << "," << common::format_g(r.timestamp_s, common::kExactDigits);
    pose_fields(f, r.belief.mean);
    for (int i = 0; i < 6; ++i) f << "," << format_csv(r.belief.cov(i, i));
    f << "," << r.readings << "," << r.fused << "," << (r.fused ? format_csv(r.nis_sum / r.fused) : "nan");
    pose_fields(f, r.dead_reckoning);
    if (r.has_truth) {
      pose_fields(f, r.truth);
      f << "," << format_csv(r.error_m) << "," << format_csv(r.error_xy_m) << "," << format_csv(r.yaw_error_rad) << ","
        << format_csv(r.dr_error_m);
    } else {
      f << ",nan,nan,nan,nan,nan,nan,nan,nan,nan,nan";
    }
    if (r.refined) {
      pose_fields(f, *r.refined);
      f << "," << (r.has_truth ? format_csv(r.refined_error_m) : "nan");
    }
    f << "\n";
  }
  if (!f) throw std::runtime_error(path + ": write failed");
}

std::vector<std::pair<std::string, std::string>> bearing_summary_rows(const BearingLog& log,
                                                                      const BearingReplayResult& r) {
  const localization::LandmarkCounters& c = r.counters;
  const auto i = [](std::int64_t v) { return std::to_string(v); };
  std::vector<std::pair<std::string, std::string>> rows = {
      {"mode", "bearing_range"},
      {"estimator", r.estimator},
      {"planar", r.planar ? "true" : "false"},
      {"frames", i(static_cast<std::int64_t>(r.track.size()))},
      {"bearing_observations", i(log.bearing_observations)},
      {"readings", i(c.readings)},
      {"readings_without_id", i(log.readings_without_id)},
      {"fused", i(c.fused)},
      {"skipped_unknown_id", i(c.unknown_id)},
      {"skipped_outside_gate", i(c.gated)},
      {"ambiguous_associations", i(c.ambiguous)},
      {"skipped_degenerate", i(c.degenerate)},
      {"mean_nis", format_csv(r.mean_nis)},
      {"ground_truth_frames", i(r.truth_frames)},
      {"rmse_m", format_csv(r.rmse_m)},
      {"rmse_xy_m", format_csv(r.rmse_xy_m)},
      {"yaw_rmse_rad", format_csv(r.yaw_rmse_rad)},
      {"dead_reckoning_rmse_m", format_csv(r.dr_rmse_m)},
  };
  if (r.particles) rows.push_back({"particles", std::to_string(r.particles)});
  if (r.particles) rows.push_back({"resamplings", i(c.resamplings)});
  if (r.refined) {
    rows.insert(rows.end(), {{"refinement", "batch"},
                             {"refined_rmse_m", format_csv(r.refined_rmse_m)},
                             {"refined_rmse_xy_m", format_csv(r.refined_rmse_xy_m)},
                             {"refined_readings_used", i(r.smoother.readings_used)},
                             {"refined_iterations", std::to_string(r.smoother.iterations)},
                             {"refined_converged", r.smoother.converged ? "true" : "false"},
                             {"refined_initial_cost", format_csv(r.smoother.initial_cost)},
                             {"refined_final_cost", format_csv(r.smoother.final_cost)}});
  }
  rows.push_back({"other_classes_skipped", describe_counts(log.skipped)});
  rows.push_back({"trailing_actions", i(log.trailing_actions)});
  if (!r.track.empty()) {
    const localization::Pose6& m = r.track.back().belief.mean;
    static const char* kNames[] = {"final_x_m",     "final_y_m",       "final_z_m",
                                   "final_yaw_rad", "final_pitch_rad", "final_roll_rad"};
    for (int k = 0; k < 6; ++k) rows.push_back({kNames[k], format_csv(m(k))});
  }
  return rows;
}

std::vector<std::string> write_bearing_plot(const BearingReplayResult& result, const localization::BeaconMap& landmarks,
                                            const std::string& dir) {
  const std::filesystem::path d(dir);
  write_ellipses_dat(result.track, d / "ellipses.dat");
  write_map_dat(landmarks, d / "landmarks.dat");
  {
    // Columns of track.csv: x 3, y 4, dr_x 18, dr_y 19, gt_x 24, gt_y 25, refined_x 34, refined_y 35.
    std::ofstream f(d / "track.gp");
    f << "set terminal pngcairo size 900,800\nset output 'track.png'\nset datafile separator ','\n"
         "set size ratio -1\nset key outside bottom center horizontal\nset grid\n"
         "set xlabel 'x [m]'\nset ylabel 'y [m]'\n"
         "set title 'losmimo-replay (bearing-range, "
      << result.estimator << "): estimate, dead reckoning" << (result.truth_frames ? ", ground truth" : "")
      << ", landmarks'\n"
      << "plot 'track.csv' skip 1 using 3:4 with lines lw 2 lc rgb '#1f77b4' title 'estimate', \\\n"
         "     'track.csv' skip 1 using 18:19 with lines dt 2 lc rgb '#7f7f7f' title 'dead reckoning', \\\n";
    if (result.refined) f << "     'track.csv' skip 1 using 34:35 with lines lc rgb '#ff7f0e' title 'refined', \\\n";
    if (result.truth_frames)
      f << "     'track.csv' skip 1 using 24:25 with lines lc rgb '#2ca02c' title 'ground truth', \\\n";
    f << "     'ellipses.dat' using 1:2:3:4:5 with ellipses lc rgb '#d62728' title '2-sigma', \\\n"
         "     'landmarks.dat' using 2:3 with points pt 5 ps 1 lc rgb 'black' title 'landmarks'\n";
    if (!f) throw std::runtime_error((d / "track.gp").string() + ": write failed");
  }
  return common::render_gnuplot(dir, {"track"}, "track.gp (and its data) written, no track.png");
}

}  // namespace losmimo::mrpt_logs
