#pragma once
// Scenario of the paper (Hanna, Yan, Cabric, section 2 and 4) with its defaults.
//
// Frame: the BS array lies in the y-z plane centred at the origin, boresight +x, z up.
// Antenna m (row r, column c, m = r * bs_cols + c) sits at
//   p_m = (0, (c - (bs_cols-1)/2) * bs_spacing_m, (r - (bs_rows-1)/2) * bs_spacing_m).
// UAVs start uniformly at random in an axis-aligned cube of side cube_side_m centred at
// cube_center_m (default 1 km along +x). R = |cube_center_m| is the link distance.

#include <Eigen/Core>
#include <cstdint>
#include <random>
#include <string>

#include "losmimo/placement/common/range.h"

namespace losmimo::placement {

// Path-loss model of one BS-antenna-to-UAV link.
enum class GainModel {
  kFarField,  // gamma = lambda / (4 pi R) for every link (the paper's approximation)
  kExact,     // gamma = lambda / (4 pi d), d the exact antenna-UAV distance
};

std::string to_string(GainModel model);
// Parses "far_field" or "exact"; throws std::invalid_argument otherwise.
GainModel gain_model_from_string(const std::string& text);

struct Scenario {
  int bs_rows = 4;
  int bs_cols = 4;
  double bs_spacing_m = 0.25;
  double carrier_hz = 60e9;
  int num_uavs = 16;
  double cube_side_m = 50.0;
  Eigen::Vector3d cube_center_m{1000.0, 0.0, 0.0};
  double snr_db = 10.0;  // per BS-antenna-to-UAV link at range R, after antenna gains
  GainModel gain_model = GainModel::kFarField;

  int num_bs_antennas() const { return bs_rows * bs_cols; }
  double wavelength_m() const;
  double range_m() const { return cube_center_m.norm(); }
  // Far-field amplitude gain lambda / (4 pi R): the unit of the normalised channel.
  double reference_gain() const;
  // Noise variance psi^2 in normalised units (psi^2 / g_R^2 = 1 / SNR).
  double noise_variance() const;
};

// The values each field accepts (validate() and the [scenario] keys). Within them every derived
// quantity (wavelength, range, distances, phases, noise variance 10^(-snr_db/10)) is finite;
// finite values beyond overflow (a 1e300 m cube centre gives an infinite range and a NaN
// channel; snr_db = 1e5 a zero noise variance).
namespace scenario_range {
inline constexpr common::Range bs_rows = common::Range::closed(1, 64);
inline constexpr common::Range bs_cols = common::Range::closed(1, 64);
inline constexpr common::Range bs_spacing_m = common::Range::above_up_to(0.0, 1e3);
inline constexpr common::Range carrier_hz = common::Range::closed(1e3, 1e15);
inline constexpr common::Range num_uavs = common::Range::closed(1, 4096);
inline constexpr common::Range cube_side_m = common::Range::closed(0.0, 1e7);
inline constexpr common::Range cube_center_m = common::Range::closed(-1e7, 1e7);  // each axis
inline constexpr common::Range snr_db = common::Range::closed(-300.0, 300.0);
}  // namespace scenario_range

// Throws common::FieldError naming the first bad field and its value; beyond the ranges, the
// start cube must lie entirely in front of the BS (x > 0).
void validate(const Scenario& scenario);

// BS antenna positions (3 x Nt, metres), in the order described above.
Eigen::Matrix3Xd bs_antenna_positions_m(const Scenario& scenario);

// Nr positions drawn uniformly in the start cube (3 x Nr, metres).
Eigen::Matrix3Xd random_start_positions_m(const Scenario& scenario, std::mt19937_64& rng);

inline constexpr double kSpeedOfLight_m_per_s = 299792458.0;

}  // namespace losmimo::placement
