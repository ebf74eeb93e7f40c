// libFuzzer target: the INI config loader.
//
// Input: INI text, as `--config FILE` gives it to both apps. It goes through what the apps do
// with a config: IniConfig::from_string, require_known, load_placement_settings and
// load_experiment_settings. The first line is also tried as a `--set section.key=value`.
// Properties (a violation traps, so libFuzzer reports it as a crash):
//   - bad input throws InputError, never another exception (an escaping exception aborts);
//   - accepted settings are usable: finite positive wavelength and noise variance, finite range
//     and a finite channel row at the start cube's centre;
//   - to_ini() of accepted settings parses back to the same INI text (a fixed point).

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "losmimo/placement/channel.h"
#include "losmimo/placement/experiment/extension.h"
#include "losmimo/placement/common/ini_config.h"

namespace lp = losmimo::placement;

namespace {
void require(bool ok) {
  if (!ok) __builtin_trap();
}

void check_usable(const lp::Scenario& sc) {
  require(std::isfinite(sc.wavelength_m()) && sc.wavelength_m() > 0.0);
  require(std::isfinite(sc.noise_variance()) && sc.noise_variance() > 0.0);
  require(std::isfinite(sc.range_m()));
  const lp::ChannelModel model(sc);
  require(model.row(sc.cube_center_m).allFinite());
}

void load_all(const losmimo::common::IniConfig& cfg) {
  try {
    const lp::PlacementSettings p = lp::load_placement_settings(cfg);
    check_usable(p.scenario);
  } catch (const losmimo::common::InputError&) {}
  try {
    const losmimo::experiment::ExperimentSettings s = losmimo::experiment::load_experiment_settings(cfg);
    check_usable(s.placement.scenario);
    const std::string ini = losmimo::experiment::to_ini(s);
    const losmimo::experiment::ExperimentSettings again =
        losmimo::experiment::load_experiment_settings(losmimo::common::IniConfig::from_string(ini, "<to_ini>"));
    require(losmimo::experiment::to_ini(again) == ini);
  } catch (const losmimo::common::InputError&) {}
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const losmimo::common::IniConfig cfg = losmimo::common::IniConfig::from_string(text, "<fuzz>");
    (void)cfg.to_string();
    try {
      cfg.require_known(lp::placement_config_keys());
    } catch (const losmimo::common::InputError&) {}
    load_all(cfg);
  } catch (const losmimo::common::InputError&) {}
  try {
    losmimo::common::IniConfig cfg;
    cfg.set_override(text.substr(0, text.find('\n')));
    load_all(cfg);
  } catch (const losmimo::common::InputError&) {}
  return 0;
}
