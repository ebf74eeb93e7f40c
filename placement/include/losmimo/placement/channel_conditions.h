#pragma once
// Beyond the pure LoS channel: Rician fading per coherence block and CSI estimation noise.
//
// Symbols (normalised units of channel.h; rows are UAVs n, columns BS antennas k):
//   L(q)     the LoS channel at the true positions q, g_nk = |L_nk| its amplitudes (1 in the
//            far field, R / d_nk with the exact gain)
//   K        the Rician K-factor (linear), from rician_k_db
//   a, b     sqrt(K / (K + 1)) and sqrt(1 / (K + 1)): a^2 + b^2 = 1, so E|H_nk|^2 = g_nk^2, the
//            LoS power of the pure LoS model
//   S_beta   the scatter of coherence block beta: i.i.d. CN(0, 1) entries (Nr x Nt)
//   sigma_e  estimation noise per entry, sigma_e^2 = 10^(-csi_snr_db / 10) relative to the
//            unit entry gain: the per-entry SNR of the channel estimate after pilot processing
//
//   true channel   H(q)  = a L(q) + b (g o S_beta)        (o: entrywise product)
//   measured CSI   Y(q)  = H(q) + sigma_e W,  W i.i.d. CN(0, 1), fresh at every measurement
//
// K = infinity (a = 1, b = 0) and csi_snr_db = infinity (sigma_e = 0) are the pure LoS channel: then
// nothing here is drawn or computed (ChannelSettings::active() is false), so results are the same
// bit for bit. "Off" is a flag, never a = sqrt(inf / inf).
//
// Blocks: iteration i of a run lies in block beta(i) = 0 for i = 0 (the start), (i - 1) / c
// after (c = coherence_iterations). Within a block S does not depend on position (block
// fading). Physically this is an approximation at 60 GHz: the diffuse part decorrelates over
// ~lambda / 2 = 2.5 mm of motion, and an iteration's probe flights are centimetres to decimetres,
// so each measurement would see an independent scatter. In distribution that limit is a LoS row
// scaled by a plus independent noise of variance b^2, so the csi_snr_db sweep at K = infinity also
// stands for it (docs/model.md).
//
// Random numbers: counter-based (kernels.h, normals), so a draw depends on (key, index) only:
//   S_beta of a run     key derive_seed(scatter_seed, {beta}): the same for every algorithm and
//                       sweep point of a trial (the experiment passes a per-trial seed)
//   W of a run          key noise_seed, consumed in measurement order (a run is sequential)
//   evaluation draws    key derive_seed(eval_seed, {d}), d < fading_eval_draws
//
// Who sees what (docs/model.md): BF's probes, the broadcast rows of every UAV, the master's Gram
// matrix, the stall test, the escape ranking and the stop test see measured CSI; GD's own row is
// its LoS model at its belief (channel.h); the reported metrics use the true channel, with
// fading the mean over fading_eval_draws draws of S at the final positions (ergodic rates).

#include <Eigen/Core>
#include <complex>
#include <cstdint>
#include <limits>
#include <string>

#include "losmimo/placement/metrics.h"

namespace losmimo::placement {

struct ChannelSettings {
  double rician_k_db = std::numeric_limits<double>::infinity();  // inf: pure LoS
  int coherence_iterations = 1;                                  // iterations per scatter draw
  double csi_snr_db = std::numeric_limits<double>::infinity();   // inf: perfect CSI
  int fading_eval_draws = 200;  // scatter draws averaged by the final metrics (finite K only)

  bool fading() const { return rician_k_db != std::numeric_limits<double>::infinity(); }
  bool noisy_csi() const { return csi_snr_db != std::numeric_limits<double>::infinity(); }
  bool active() const { return fading() || noisy_csi(); }
};

// Accepted ranges (the key table states them too).
inline constexpr double kMinRicianK_db = -50.0;
inline constexpr double kMaxRicianK_db = 100.0;
inline constexpr double kMinCsiSnr_db = -50.0;
inline constexpr double kMaxCsiSnr_db = 200.0;
inline constexpr int kMaxCoherenceIterations = 1'000'000;
inline constexpr int kMaxFadingEvalDraws = 100'000;

// Throws common::FieldError naming the field (NaN, -inf, out of range, a block of 0 iterations).
void validate(const ChannelSettings& settings);

// A level in dB as an INI value: "inf" (off), or a finite number in [lo_db, hi_db]. Throws
// common::InputError "<where>: ..." otherwise (NaN, "-inf", out of range, not a number).
double parse_db_or_inf(const std::string& text, const std::string& where, double lo_db, double hi_db);
// "inf" or the shortest exact text of a finite value.
std::string format_db_or_inf(double value_db);

// n i.i.d. CN(0, 1) numbers (real and imaginary parts N(0, 1/2)), numbers first .. first + n - 1
// of the counter-based stream `key` (8 complex numbers per block of the kernels' normals).
void complex_normals(std::uint64_t key, std::uint64_t first, int n, std::complex<double>* z);

// A run's channel conditions: the current block's scatter and the estimation-noise stream.
class ChannelConditions {
 public:
  ChannelConditions() = default;  // inactive
  ChannelConditions(const ChannelSettings& settings, int num_uavs, int num_antennas, std::uint64_t scatter_seed,
                    std::uint64_t noise_seed);

  const ChannelSettings& settings() const { return settings_; }
  bool active() const { return settings_.active(); }
  int num_uavs() const { return num_uavs_; }
  int num_antennas() const { return num_antennas_; }
  double los_weight() const { return a_; }      // a
  double scatter_weight() const { return b_; }  // b
  double noise_sigma() const { return sigma_e_; }

  // The block of an iteration (0 for the start).
  int block_of(int iteration) const;
  // Moves to the block of `iteration`; true if that is a new block (the scatter was redrawn).
  bool begin_iteration(int iteration);
  int block() const { return block_; }
  // S of the current block (Nr x Nt; empty without fading).
  const Eigen::MatrixXcd& scatter() const { return scatter_; }

  // UAV m's LoS row x (length Nt) becomes its true row a x + b (|x| o S_m), in place.
  void fade_row(int m, Eigen::VectorXcd& x) const;
  // ... and then its measured row: plus sigma_e W with the next numbers of the noise stream.
  void measure_row(int m, Eigen::VectorXcd& x);

  // The expected objective f of measured CSI at a perfect placement (orthogonal LoS rows or
  // columns): with P = min(Nr, Nt) the Gram matrix's size, Q = max(Nr, Nt) and v = b^2 + sigma_e^2
  // the variance of everything but a L,
  //   F0 = P (P - 1) Q (2 a^2 v + v^2)
  // (far field; each off-diagonal Gram entry is a sum of Q independent terms). 0 when inactive.
  // Below ~F0 a measured f no longer says which placement is better: the planners' escapes act
  // only above 2 F0.
  double noise_floor_objective() const { return noise_floor_f_; }

 private:
  void draw_scatter();

  ChannelSettings settings_;
  int num_uavs_ = 0;
  int num_antennas_ = 0;
  double a_ = 1.0, b_ = 0.0, sigma_e_ = 0.0;
  std::uint64_t scatter_seed_ = 0;
  std::uint64_t noise_seed_ = 0;
  std::uint64_t noise_next_ = 0;  // the next complex number of the noise stream
  int block_ = -1;
  Eigen::MatrixXcd scatter_;
  double noise_floor_f_ = 0.0;
};

// The true channel's metrics at fixed positions. Without fading: `los` alone (draws = 0), and
// the means below equal it. With fading: the means over `draws` = fading_eval_draws scatter
// draws of a L + b (g o S_d) (ICN, f and the sum rates averaged linearly: ergodic rates; the
// SINR of each stream averaged in dB, as the experiment's mean_* columns average streams).
struct FadedLinkMetrics {
  LinkMetrics los;  // the LoS channel L
  int draws = 0;
  double icn = 0.0;
  double objective = 0.0;
  double sum_rate_nv_bps_hz = 0.0;
  double sum_rate_zf_bps_hz = 0.0;
  Eigen::VectorXd sinr_nv_db, sinr_zf_db, sinr_mf_db;  // per stream
};
FadedLinkMetrics evaluate_link_faded(const Eigen::MatrixXcd& H_los, double noise_variance,
                                     const ChannelSettings& settings, std::uint64_t eval_seed);

}  // namespace losmimo::placement
