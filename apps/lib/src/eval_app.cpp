#include "losmimo/apps/lib/eval_app.h"

#include <cmath>
#include <iomanip>
#include <ostream>

#include "losmimo/apps/lib/exit_codes.h"
#include "losmimo/apps/lib/unused_keys.h"
#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/experiment/extension.h"
#include "losmimo/placement/channel.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/placement/positions_csv.h"
#include "losmimo/placement/settings.h"
#include "kernel_isa.h"
#include "messages.h"

namespace losmimo::apps {

using namespace placement;
using common::IniConfig;
using common::InputError;

namespace {
void print_csv(const LinkMetrics& m, std::ostream& out) {
  out << std::setprecision(10);
  out << "stream,sinr_nv_db,sinr_zf_db,sinr_mf_db\n";
  for (Eigen::Index k = 0; k < m.sinr.nv.size(); ++k) {
    out << k + 1 << "," << to_db(m.sinr.nv(k)) << "," << to_db(m.sinr.zf(k)) << "," << to_db(m.sinr.mf(k)) << "\n";
  }
  out << "icn," << m.icn << "\nobjective," << m.objective << "\nsum_rate_nv_bps_hz," << m.sum_rate_nv_bps_hz
      << "\nsum_rate_zf_bps_hz," << m.sum_rate_zf_bps_hz << "\n";
}

void print_table(const LinkMetrics& m, int nr, int num_antennas, std::ostream& out) {
  out << std::fixed << std::setprecision(2);
  out << "stream   NV SINR [dB]   ZF SINR [dB]   MF SINR [dB]\n";
  for (Eigen::Index k = 0; k < m.sinr.nv.size(); ++k) {
    out << std::setw(6) << k + 1 << std::setw(15) << to_db(m.sinr.nv(k)) << std::setw(15) << to_db(m.sinr.zf(k))
        << std::setw(15) << to_db(m.sinr.mf(k)) << "\n";
  }
  out << std::setprecision(4) << "ICN                    " << m.icn << "\n"
      << std::scientific << "objective f            " << m.objective << std::fixed << "\n"
      << "sum rate NV [bit/s/Hz] " << m.sum_rate_nv_bps_hz << "\n"
      << "sum rate ZF [bit/s/Hz] " << m.sum_rate_zf_bps_hz << "\n";
  if (nr < num_antennas) {
    out << "note: " << nr << " UAVs < " << num_antennas
        << " BS antennas: one stream per UAV, with linear processing at the BS (docs/model.md)\n";
  }
}
}  // namespace

int run_eval_app(const EvalOptions& options, std::ostream& out, std::ostream& err) {
  try {
    kernel_isa_name();  // a bad LOSMIMO_ISA stops here: kExitBadInput
    common::IniConfig config =
        options.config_path.empty() ? common::IniConfig() : common::IniConfig::from_file(options.config_path);
    for (const std::string& o : options.overrides) config.set_override(o);
    // An experiment config (e.g. datasets/configs/paper.ini) is a valid scenario source too; its
    // [experiment] keys are not used here, but checked like everything else.
    config.require_known(experiment::experiment_config_keys());
    if (config.has_section("experiment")) experiment::load_experiment_settings(config);
    const PlacementSettings settings = load_placement_settings(config);
    require_los_channel(settings.channel, config, "losmimo-eval");
    refuse_unused_overrides(config, options.overrides, {{"losmimo-eval", {}}});
    PositionsSelection selection;
    for (const std::string& s : options.selection) {
      const std::size_t eq = s.find('=');
      if (eq == std::string::npos || eq == 0) {
        throw InputError("--select " + s + ": expected column=value (e.g. --select trial=0)");
      }
      selection.emplace_back(s.substr(0, eq), s.substr(eq + 1));
    }
    const Eigen::Matrix3Xd q_m = read_positions_csv(options.positions_path, 65536, selection);
    const ChannelModel model(settings.scenario);
    for (Eigen::Index n = 0; n < q_m.cols(); ++n) {
      for (Eigen::Index k = 0; k < model.num_antennas(); ++k) {
        if ((q_m.col(n) - model.antennas_m().col(k)).norm() < 1e-3) {
          throw common::InputError(options.positions_path + ": UAV " + std::to_string(n + 1) + " sits on BS antenna " +
                                   std::to_string(k + 1));
        }
      }
    }
    const LinkMetrics m = evaluate_link(model.matrix(q_m), settings.scenario.noise_variance());
    if (options.csv) {
      print_csv(m, out);
    } else {
      print_table(m, static_cast<int>(q_m.cols()), model.num_antennas(), out);
    }
    return kExitOk;
  } catch (...) {
    return report_current_exception(err, "losmimo-eval");
  }
}

}  // namespace losmimo::apps
