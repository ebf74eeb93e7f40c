#include "losmimo/placement/channel_conditions.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "losmimo/placement/common/field_error.h"
#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/common/seed.h"
#include "losmimo/placement/kernels.h"

namespace losmimo::placement {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kComplexPerBlock = kernels::kNormalsPerBlock / 2;  // a block's Box-Muller pairs

// "rician_k_db = nan: must be a number in [-50, 100] dB or inf"
[[noreturn]] void bad_db(const char* field, double value, double lo, double hi) {
  std::ostringstream msg;
  msg << "channel." << field << " = " << value << ": must be a number in [" << lo << ", " << hi << "] dB or inf";
  throw common::FieldError(field, msg.str());
}

// The mean of the per-draw values of a vector, accumulated in place.
void accumulate(Eigen::VectorXd& sum, const Eigen::VectorXd& linear) {
  if (sum.size() != linear.size()) sum = Eigen::VectorXd::Zero(linear.size());
  for (Eigen::Index k = 0; k < linear.size(); ++k) sum(k) += to_db(linear(k));
}
}  // namespace

void validate(const ChannelSettings& s) {
  if (!(s.rician_k_db == kInf || (s.rician_k_db >= kMinRicianK_db && s.rician_k_db <= kMaxRicianK_db)))
    bad_db("rician_k_db", s.rician_k_db, kMinRicianK_db, kMaxRicianK_db);
  if (!(s.csi_snr_db == kInf || (s.csi_snr_db >= kMinCsiSnr_db && s.csi_snr_db <= kMaxCsiSnr_db)))
    bad_db("csi_snr_db", s.csi_snr_db, kMinCsiSnr_db, kMaxCsiSnr_db);
  if (s.coherence_iterations < 1 || s.coherence_iterations > kMaxCoherenceIterations) {
    throw common::FieldError("coherence_iterations",
                             "channel.coherence_iterations = " + std::to_string(s.coherence_iterations) +
                                 ": must be in [1, 1000000] (a block lasts at least one iteration)");
  }
  if (s.fading_eval_draws < 1 || s.fading_eval_draws > kMaxFadingEvalDraws) {
    throw common::FieldError("fading_eval_draws", "channel.fading_eval_draws = " + std::to_string(s.fading_eval_draws) +
                                                      ": must be in [1, 100000]");
  }
}

double parse_db_or_inf(const std::string& text, const std::string& where, double lo_db, double hi_db) {
  if (text == "inf") return kInf;
  const double v = common::parse_double(text, where);
  if (!(v >= lo_db && v <= hi_db)) {
    throw common::InputError(where + ": " + text + ": must be a number in [" + common::format_double(lo_db) + ", " +
                             common::format_double(hi_db) + "] dB, or inf");
  }
  return v;
}

std::string format_db_or_inf(double value_db) { return value_db == kInf ? "inf" : common::format_double(value_db); }

void complex_normals(std::uint64_t key, std::uint64_t first, int n, std::complex<double>* z) {
  if (n <= 0) return;
  const std::uint64_t first_block = first / kComplexPerBlock;
  const std::uint64_t last_block = (first + static_cast<std::uint64_t>(n) - 1) / kComplexPerBlock;
  const int blocks = static_cast<int>(last_block - first_block + 1);
  thread_local std::vector<double> normals;
  normals.resize(static_cast<std::size_t>(blocks) * 2 * kComplexPerBlock);
  kernels::active_kernels().normals(key, first_block, normals.data(), blocks);
  const double scale = std::sqrt(0.5);
  for (int i = 0; i < n; ++i) {
    const std::uint64_t c = first + static_cast<std::uint64_t>(i) - first_block * kComplexPerBlock;
    const std::uint64_t b = c / kComplexPerBlock, lane = c % kComplexPerBlock;
    const double re = normals[2 * kComplexPerBlock * b + lane];
    const double im = normals[2 * kComplexPerBlock * b + kComplexPerBlock + lane];
    z[i] = std::complex<double>(scale * re, scale * im);
  }
}

ChannelConditions::ChannelConditions(const ChannelSettings& settings, int num_uavs, int num_antennas,
                                     std::uint64_t scatter_seed, std::uint64_t noise_seed)
    : settings_(settings),
      num_uavs_(num_uavs),
      num_antennas_(num_antennas),
      scatter_seed_(scatter_seed),
      noise_seed_(noise_seed) {
  validate(settings_);
  if (num_uavs < 1 || num_antennas < 1) {
    throw std::invalid_argument("ChannelConditions: " + std::to_string(num_uavs) + " UAVs, " +
                                std::to_string(num_antennas) + " antennas");
  }
  if (settings_.fading()) {
    const double k = std::pow(10.0, settings_.rician_k_db / 10.0);
    a_ = std::sqrt(k / (k + 1.0));
    b_ = std::sqrt(1.0 / (k + 1.0));
  }
  if (settings_.noisy_csi()) sigma_e_ = std::pow(10.0, -settings_.csi_snr_db / 20.0);
  const double p = std::min(num_uavs, num_antennas), q = std::max(num_uavs, num_antennas);
  const double v = b_ * b_ + sigma_e_ * sigma_e_;
  noise_floor_f_ = active() ? p * (p - 1.0) * q * (2.0 * a_ * a_ * v + v * v) : 0.0;
  begin_iteration(0);
}

int ChannelConditions::block_of(int iteration) const {
  return iteration <= 0 ? 0 : (iteration - 1) / settings_.coherence_iterations;
}

bool ChannelConditions::begin_iteration(int iteration) {
  const int block = block_of(iteration);
  if (block == block_) return false;
  block_ = block;
  if (settings_.fading()) draw_scatter();
  return true;
}

void ChannelConditions::draw_scatter() {
  // Row-major: UAV n's scatter is numbers n Nt .. n Nt + Nt - 1 of the block's stream.
  std::vector<std::complex<double>> z(static_cast<std::size_t>(num_uavs_) * num_antennas_);
  complex_normals(common::derive_seed(scatter_seed_, {static_cast<std::uint64_t>(block_)}), 0,
                  static_cast<int>(z.size()), z.data());
  scatter_.resize(num_uavs_, num_antennas_);
  for (int n = 0; n < num_uavs_; ++n) {
    for (int k = 0; k < num_antennas_; ++k) scatter_(n, k) = z[static_cast<std::size_t>(n) * num_antennas_ + k];
  }
}

void ChannelConditions::fade_row(int m, Eigen::VectorXcd& x) const {
  if (!settings_.fading()) return;
  for (Eigen::Index k = 0; k < x.size(); ++k) x(k) = a_ * x(k) + b_ * std::abs(x(k)) * scatter_(m, k);
}

void ChannelConditions::measure_row(int m, Eigen::VectorXcd& x) {
  fade_row(m, x);
  if (!settings_.noisy_csi()) return;
  thread_local std::vector<std::complex<double>> w;
  w.resize(static_cast<std::size_t>(x.size()));
  complex_normals(noise_seed_, noise_next_, static_cast<int>(x.size()), w.data());
  noise_next_ += static_cast<std::uint64_t>(x.size());
  for (Eigen::Index k = 0; k < x.size(); ++k) x(k) += sigma_e_ * w[static_cast<std::size_t>(k)];
}

FadedLinkMetrics evaluate_link_faded(const Eigen::MatrixXcd& H_los, double noise_variance,
                                     const ChannelSettings& settings, std::uint64_t eval_seed) {
  FadedLinkMetrics out;
  out.los = evaluate_link(H_los, noise_variance);
  const auto db = [](const Eigen::VectorXd& linear) {
    Eigen::VectorXd v(linear.size());
    for (Eigen::Index k = 0; k < linear.size(); ++k) v(k) = to_db(linear(k));
    return v;
  };
  if (!settings.fading()) {
    out.icn = out.los.icn;
    out.objective = out.los.objective;
    out.sum_rate_nv_bps_hz = out.los.sum_rate_nv_bps_hz;
    out.sum_rate_zf_bps_hz = out.los.sum_rate_zf_bps_hz;
    out.sinr_nv_db = db(out.los.sinr.nv);
    out.sinr_zf_db = db(out.los.sinr.zf);
    out.sinr_mf_db = db(out.los.sinr.mf);
    return out;
  }
  const double k = std::pow(10.0, settings.rician_k_db / 10.0);
  const double a = std::sqrt(k / (k + 1.0)), b = std::sqrt(1.0 / (k + 1.0));
  const Eigen::Index nr = H_los.rows(), nt = H_los.cols();
  const Eigen::MatrixXd gain = H_los.cwiseAbs();
  std::vector<std::complex<double>> z(static_cast<std::size_t>(nr * nt));
  Eigen::MatrixXcd H(nr, nt);
  out.draws = settings.fading_eval_draws;
  for (int d = 0; d < out.draws; ++d) {
    complex_normals(common::derive_seed(eval_seed, {static_cast<std::uint64_t>(d)}), 0, static_cast<int>(z.size()),
                    z.data());
    for (Eigen::Index n = 0; n < nr; ++n) {
      for (Eigen::Index c = 0; c < nt; ++c) {
        H(n, c) = a * H_los(n, c) + b * gain(n, c) * z[static_cast<std::size_t>(n * nt + c)];
      }
    }
    const LinkMetrics m = evaluate_link(H, noise_variance);
    out.icn += m.icn;
    out.objective += m.objective;
    out.sum_rate_nv_bps_hz += m.sum_rate_nv_bps_hz;
    out.sum_rate_zf_bps_hz += m.sum_rate_zf_bps_hz;
    accumulate(out.sinr_nv_db, m.sinr.nv);
    accumulate(out.sinr_zf_db, m.sinr.zf);
    accumulate(out.sinr_mf_db, m.sinr.mf);
  }
  const double inv = 1.0 / out.draws;
  out.icn *= inv;
  out.objective *= inv;
  out.sum_rate_nv_bps_hz *= inv;
  out.sum_rate_zf_bps_hz *= inv;
  out.sinr_nv_db *= inv;
  out.sinr_zf_db *= inv;
  out.sinr_mf_db *= inv;
  return out;
}

}  // namespace losmimo::placement
