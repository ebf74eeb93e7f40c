#include "losmimo/common/format.h"
#include "losmimo/common/ini_config.h"
#include "losmimo/placement/settings.h"

#include <iomanip>
#include <limits>
#include <sstream>

namespace losmimo::placement {

std::map<std::string, std::set<std::string>> placement_config_keys() {
  return {
      {"scenario",
       {"bs_rows", "bs_cols", "bs_spacing_m", "carrier_hz", "num_uavs", "cube_side_m",
        "cube_center_x_m", "cube_center_y_m", "cube_center_z_m", "snr_db", "gain_model"}},
      {"errors", {"sigma_loc_m", "sigma_act_m"}},
      {"placement", {"target_icn", "max_iterations"}},
      {"gd", {"step", "decay", "max_move_m", "backtracking", "max_halvings", "escape",
              "stall_window", "stall_min_decrease", "escape_half_grid", "escape_uavs", "depth_step_gain"}},
      {"bf", {"step", "decay", "contraction", "min_step_m", "escape", "stall_window",
              "stall_min_decrease"}},
  };
}

namespace {
constexpr long long kIntMax = std::numeric_limits<int>::max();

// Runs a validator and re-throws its message as an common::InputError located in the config.
template <typename Validate>
void check(const common::IniConfig& cfg, const std::string& section, Validate&& validate_fn) {
  try {
    validate_fn();
  } catch (const std::invalid_argument& e) {
    // The validators name "section.key"; point at the line when the key came from the file.
    const std::string msg = e.what();
    const std::size_t dot = msg.find('.');
    const std::size_t end = msg.find_first_of(" =", dot);
    if (dot != std::string::npos && end != std::string::npos && msg.compare(0, dot, section) == 0) {
      const std::string key = msg.substr(dot + 1, end - dot - 1);
      if (cfg.has(section, key)) throw common::InputError(cfg.where(section, key) + ": " + msg);
    }
    throw common::InputError("config: " + msg);
  }
}
}  // namespace

PlacementSettings load_placement_settings(const common::IniConfig& cfg) {
  PlacementSettings s;
  Scenario& sc = s.scenario;
  sc.bs_rows = static_cast<int>(cfg.get_integer("scenario", "bs_rows", sc.bs_rows, 1, 64));
  sc.bs_cols = static_cast<int>(cfg.get_integer("scenario", "bs_cols", sc.bs_cols, 1, 64));
  sc.bs_spacing_m = cfg.get_double("scenario", "bs_spacing_m", sc.bs_spacing_m);
  sc.carrier_hz = cfg.get_double("scenario", "carrier_hz", sc.carrier_hz);
  sc.num_uavs = static_cast<int>(cfg.get_integer("scenario", "num_uavs", sc.num_uavs, 1, 4096));
  sc.cube_side_m = cfg.get_double("scenario", "cube_side_m", sc.cube_side_m);
  sc.cube_center_m.x() = cfg.get_double("scenario", "cube_center_x_m", sc.cube_center_m.x());
  sc.cube_center_m.y() = cfg.get_double("scenario", "cube_center_y_m", sc.cube_center_m.y());
  sc.cube_center_m.z() = cfg.get_double("scenario", "cube_center_z_m", sc.cube_center_m.z());
  sc.snr_db = cfg.get_double("scenario", "snr_db", sc.snr_db);
  if (cfg.has("scenario", "gain_model")) {
    try {
      sc.gain_model = gain_model_from_string(cfg.get_string("scenario", "gain_model", ""));
    } catch (const std::invalid_argument& e) {
      throw common::InputError(cfg.where("scenario", "gain_model") + ": " + e.what());
    }
  }
  check(cfg, "scenario", [&] { validate(sc); });

  s.errors.sigma_loc_m = cfg.get_double("errors", "sigma_loc_m", s.errors.sigma_loc_m);
  s.errors.sigma_act_m = cfg.get_double("errors", "sigma_act_m", s.errors.sigma_act_m);
  check(cfg, "errors", [&] { validate(s.errors); });

  s.run.target_icn = cfg.get_double("placement", "target_icn", s.run.target_icn);
  s.run.max_iterations = static_cast<int>(
      cfg.get_integer("placement", "max_iterations", s.run.max_iterations, 0, 10'000'000));
  s.run.noise_variance = sc.noise_variance();
  check(cfg, "placement", [&] { validate(s.run); });

  GdOptions& gd = s.gd;
  gd.step = cfg.get_double("gd", "step", gd.step);
  gd.decay = cfg.get_double("gd", "decay", gd.decay);
  gd.max_move_m = cfg.get_double("gd", "max_move_m", gd.max_move_m);
  gd.backtracking = cfg.get_bool("gd", "backtracking", gd.backtracking);
  gd.max_halvings = static_cast<int>(cfg.get_integer("gd", "max_halvings", gd.max_halvings, 0, 60));
  gd.escape = cfg.get_bool("gd", "escape", gd.escape);
  gd.stall_window = static_cast<int>(cfg.get_integer("gd", "stall_window", gd.stall_window, 1, kIntMax));
  gd.stall_min_decrease = cfg.get_double("gd", "stall_min_decrease", gd.stall_min_decrease);
  gd.escape_half_grid =
      static_cast<int>(cfg.get_integer("gd", "escape_half_grid", gd.escape_half_grid, 1, 256));
  gd.escape_uavs = static_cast<int>(cfg.get_integer("gd", "escape_uavs", gd.escape_uavs, 1, 100000));
  gd.depth_step_gain = cfg.get_double("gd", "depth_step_gain", gd.depth_step_gain);
  check(cfg, "gd", [&] { validate(gd); });

  BfOptions& bf = s.bf;
  bf.step = cfg.get_double("bf", "step", bf.step);
  bf.decay = cfg.get_double("bf", "decay", bf.decay);
  bf.contraction = cfg.get_double("bf", "contraction", bf.contraction);
  bf.min_step_m = cfg.get_double("bf", "min_step_m", bf.min_step_m);
  bf.escape = cfg.get_bool("bf", "escape", bf.escape);
  bf.stall_window = static_cast<int>(cfg.get_integer("bf", "stall_window", bf.stall_window, 1, kIntMax));
  bf.stall_min_decrease = cfg.get_double("bf", "stall_min_decrease", bf.stall_min_decrease);
  check(cfg, "bf", [&] { validate(bf); });
  return s;
}

std::string to_ini(const PlacementSettings& s) {
  std::ostringstream o;
  o << std::setprecision(17);
  const Scenario& sc = s.scenario;
  o << "[scenario]\n"
    << "bs_rows = " << sc.bs_rows << "\nbs_cols = " << sc.bs_cols
    << "\nbs_spacing_m = " << common::format_double(sc.bs_spacing_m) << "\ncarrier_hz = " << common::format_double(sc.carrier_hz)
    << "\nnum_uavs = " << sc.num_uavs << "\ncube_side_m = " << common::format_double(sc.cube_side_m)
    << "\ncube_center_x_m = " << common::format_double(sc.cube_center_m.x()) << "\ncube_center_y_m = " << common::format_double(sc.cube_center_m.y())
    << "\ncube_center_z_m = " << common::format_double(sc.cube_center_m.z()) << "\nsnr_db = " << common::format_double(sc.snr_db)
    << "\ngain_model = " << to_string(sc.gain_model) << "\n\n";
  o << "[errors]\nsigma_loc_m = " << common::format_double(s.errors.sigma_loc_m) << "\nsigma_act_m = " << common::format_double(s.errors.sigma_act_m)
    << "\n\n";
  o << "[placement]\ntarget_icn = " << common::format_double(s.run.target_icn) << "\nmax_iterations = " << s.run.max_iterations
    << "\n\n";
  const auto b = [](bool v) { return v ? "true" : "false"; };
  o << "[gd]\nstep = " << common::format_double(s.gd.step) << "\ndecay = " << common::format_double(s.gd.decay) << "\nmax_move_m = " << common::format_double(s.gd.max_move_m)
    << "\nbacktracking = " << b(s.gd.backtracking) << "\nmax_halvings = " << s.gd.max_halvings
    << "\nescape = " << b(s.gd.escape) << "\nstall_window = " << s.gd.stall_window
    << "\nstall_min_decrease = " << common::format_double(s.gd.stall_min_decrease) << "\n";
  // The large-swarm keys only when set, so that the defaults' text (paper.ini) is unchanged.
  const GdOptions gd_defaults;
  if (s.gd.escape_half_grid != gd_defaults.escape_half_grid) o << "escape_half_grid = " << s.gd.escape_half_grid << "\n";
  if (s.gd.escape_uavs != gd_defaults.escape_uavs) o << "escape_uavs = " << s.gd.escape_uavs << "\n";
  if (s.gd.depth_step_gain != gd_defaults.depth_step_gain) o << "depth_step_gain = " << common::format_double(s.gd.depth_step_gain) << "\n";
  o << "\n";
  o << "[bf]\nstep = " << common::format_double(s.bf.step) << "\ndecay = " << common::format_double(s.bf.decay) << "\ncontraction = " << common::format_double(s.bf.contraction)
    << "\nmin_step_m = " << common::format_double(s.bf.min_step_m) << "\nescape = " << b(s.bf.escape)
    << "\nstall_window = " << s.bf.stall_window << "\nstall_min_decrease = " << common::format_double(s.bf.stall_min_decrease)
    << "\n";
  return o.str();
}

}  // namespace losmimo::placement
