#include "losmimo/placement/scenario.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "losmimo/placement/common/field_error.h"
#include "losmimo/placement/common/format.h"

namespace losmimo::placement {

std::string to_string(GainModel model) { return model == GainModel::kExact ? "exact" : "far_field"; }

GainModel gain_model_from_string(const std::string& text) {
  if (text == "far_field") return GainModel::kFarField;
  if (text == "exact") return GainModel::kExact;
  throw std::invalid_argument("gain_model must be 'far_field' or 'exact', got '" + text + "'");
}

double Scenario::wavelength_m() const { return kSpeedOfLight_m_per_s / carrier_hz; }

double Scenario::reference_gain() const { return wavelength_m() / (4.0 * M_PI * range_m()); }

double Scenario::noise_variance() const { return std::pow(10.0, -snr_db / 10.0); }

void validate(const Scenario& s) {
  namespace r = scenario_range;
  const auto require = [](const common::Range& range, double value, const char* field) {
    common::require_field_in(range, value, "scenario", field);
  };
  require(r::bs_rows, s.bs_rows, "bs_rows");
  require(r::bs_cols, s.bs_cols, "bs_cols");
  require(r::bs_spacing_m, s.bs_spacing_m, "bs_spacing_m");
  require(r::carrier_hz, s.carrier_hz, "carrier_hz");
  require(r::num_uavs, s.num_uavs, "num_uavs");
  require(r::cube_side_m, s.cube_side_m, "cube_side_m");
  require(r::cube_center_m, s.cube_center_m.x(), "cube_center_x_m");
  require(r::cube_center_m, s.cube_center_m.y(), "cube_center_y_m");
  require(r::cube_center_m, s.cube_center_m.z(), "cube_center_z_m");
  if (!(s.cube_center_m.x() - 0.5 * s.cube_side_m > 0.0)) {
    throw common::FieldError("cube_center_x_m",
                             "scenario.cube_center_x_m = " + common::format_double(s.cube_center_m.x()) +
                                 ": the start cube must lie entirely in front of the BS (x > 0)");
  }
  require(r::snr_db, s.snr_db, "snr_db");
}

Eigen::Matrix3Xd bs_antenna_positions_m(const Scenario& s) {
  Eigen::Matrix3Xd p(3, s.num_bs_antennas());
  for (int r = 0; r < s.bs_rows; ++r) {
    for (int c = 0; c < s.bs_cols; ++c) {
      p.col(r * s.bs_cols + c) << 0.0, (c - 0.5 * (s.bs_cols - 1)) * s.bs_spacing_m,
          (r - 0.5 * (s.bs_rows - 1)) * s.bs_spacing_m;
    }
  }
  return p;
}

Eigen::Matrix3Xd random_start_positions_m(const Scenario& s, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(-0.5, 0.5);
  Eigen::Matrix3Xd q(3, s.num_uavs);
  for (int n = 0; n < s.num_uavs; ++n) {
    for (int i = 0; i < 3; ++i) q(i, n) = s.cube_center_m(i) + s.cube_side_m * unit(rng);
  }
  return q;
}

}  // namespace losmimo::placement
