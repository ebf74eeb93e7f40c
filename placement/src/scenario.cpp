#include "losmimo/placement/scenario.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "losmimo/common/field_error.h"

namespace losmimo::placement {

std::string to_string(GainModel model) {
  return model == GainModel::kExact ? "exact" : "far_field";
}

GainModel gain_model_from_string(const std::string& text) {
  if (text == "far_field") return GainModel::kFarField;
  if (text == "exact") return GainModel::kExact;
  throw std::invalid_argument("gain_model must be 'far_field' or 'exact', got '" + text + "'");
}

double Scenario::wavelength_m() const { return kSpeedOfLight_m_per_s / carrier_hz; }

double Scenario::reference_gain() const { return wavelength_m() / (4.0 * M_PI * range_m()); }

double Scenario::noise_variance() const { return std::pow(10.0, -snr_db / 10.0); }

namespace {
template <typename T>
[[noreturn]] void bad_field(const char* field, const T& value, const char* requirement) {
  std::ostringstream msg;
  msg << "scenario." << field << " = " << value << ": " << requirement;
  throw common::FieldError(field, msg.str());
}
}  // namespace

// Physical limits: within them every derived quantity (wavelength, range, distances, phases,
// noise variance 10^(-snr_db/10)) is finite. Finite values beyond them overflow (a 1e300 m
// cube centre gives an infinite range and a NaN channel; snr_db = 1e5 a zero noise variance).
constexpr double kMaxLength_m = 1e7;
constexpr double kMaxSpacing_m = 1e3;
constexpr double kMinCarrier_hz = 1e3;
constexpr double kMaxCarrier_hz = 1e15;
constexpr double kMaxAbsSnr_db = 300.0;

void validate(const Scenario& s) {
  if (s.bs_rows < 1 || s.bs_rows > 64) bad_field("bs_rows", s.bs_rows, "must be in [1, 64]");
  if (s.bs_cols < 1 || s.bs_cols > 64) bad_field("bs_cols", s.bs_cols, "must be in [1, 64]");
  if (!(s.bs_spacing_m > 0.0 && s.bs_spacing_m <= kMaxSpacing_m))
    bad_field("bs_spacing_m", s.bs_spacing_m, "must be in (0, 1e3] m");
  if (!(s.carrier_hz >= kMinCarrier_hz && s.carrier_hz <= kMaxCarrier_hz))
    bad_field("carrier_hz", s.carrier_hz, "must be in [1e3, 1e15] Hz");
  if (s.num_uavs < 1 || s.num_uavs > 4096) bad_field("num_uavs", s.num_uavs, "must be in [1, 4096]");
  if (!(s.cube_side_m >= 0.0 && s.cube_side_m <= kMaxLength_m))
    bad_field("cube_side_m", s.cube_side_m, "must be in [0, 1e7] m");
  const char* const center_keys[3] = {"cube_center_x_m", "cube_center_y_m", "cube_center_z_m"};
  for (int i = 0; i < 3; ++i) {
    if (!(std::abs(s.cube_center_m(i)) <= kMaxLength_m))
      bad_field(center_keys[i], s.cube_center_m(i), "must be in [-1e7, 1e7] m");
  }
  if (!(s.cube_center_m.x() - 0.5 * s.cube_side_m > 0.0))
    bad_field("cube_center_x_m", s.cube_center_m.x(), "the start cube must lie entirely in front of the BS (x > 0)");
  if (!(std::abs(s.snr_db) <= kMaxAbsSnr_db)) bad_field("snr_db", s.snr_db, "must be in [-300, 300] dB");
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
