#include "losmimo/localization/resampling.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace losmimo::localization {

namespace {

// U(0, 1) from 32 random bits, open at both ends (so no index is skipped at u = 0 or u = 1).
double uniform_open01(mrpt::random::CRandomGenerator& rng) {
  constexpr double kTwoPow32 = 4294967296.0;
  return (static_cast<double>(rng.drawUniform32bit()) + 0.5) / kTwoPow32;
}

// Appends, for each sorted point u in (0, 1], the index j with Q_{j-1} < u <= Q_j.
void invert_cdf(const std::vector<double>& weights, const std::vector<double>& sorted_u,
                std::vector<std::size_t>& out) {
  const std::size_t n = weights.size();
  std::size_t j = 0;
  double cumulative = weights[0];
  for (const double u : sorted_u) {
    while (cumulative < u && j + 1 < n) {
      ++j;
      cumulative += weights[j];
    }
    out.push_back(j);
  }
}

}  // namespace

std::vector<double> normalized_weights(const std::vector<double>& log_weights) {
  const std::size_t n = log_weights.size();
  double max_log_w = -std::numeric_limits<double>::infinity();
  for (const double lw : log_weights) {
    if (std::isfinite(lw)) max_log_w = std::max(max_log_w, lw);
  }
  std::vector<double> w(n, 0.0);
  double sum = 0.0;
  if (std::isfinite(max_log_w)) {
    for (std::size_t i = 0; i < n; ++i) {
      w[i] = std::isfinite(log_weights[i]) ? std::exp(log_weights[i] - max_log_w) : 0.0;
      sum += w[i];
    }
  }
  if (!(sum > 0.0) || !std::isfinite(sum)) {
    std::fill(w.begin(), w.end(), 1.0 / static_cast<double>(n));
    return w;
  }
  for (double& wi : w) wi /= sum;
  return w;
}

double normalized_ess(const std::vector<double>& log_weights) {
  if (log_weights.empty()) return 0.0;
  const std::vector<double> w = normalized_weights(log_weights);
  double sum_sq = 0.0;
  for (const double wi : w) sum_sq += wi * wi;
  return 1.0 / (static_cast<double>(w.size()) * sum_sq);
}

std::vector<std::size_t> resampling_indices(ResamplingMethod method, const std::vector<double>& log_weights,
                                            mrpt::random::CRandomGenerator& rng) {
  if (log_weights.empty()) {
    throw std::invalid_argument("localization: resampling_indices needs at least one weight");
  }
  const std::size_t n = log_weights.size();
  const double n_d = static_cast<double>(n);
  const std::vector<double> w = normalized_weights(log_weights);
  std::vector<std::size_t> out;
  out.reserve(n);
  std::vector<double> u;
  u.reserve(n);
  switch (method) {
    case ResamplingMethod::kMultinomial: {
      for (std::size_t k = 0; k < n; ++k) u.push_back(uniform_open01(rng));
      std::sort(u.begin(), u.end());
      invert_cdf(w, u, out);
      break;
    }
    case ResamplingMethod::kStratified: {
      for (std::size_t k = 0; k < n; ++k) {
        u.push_back((static_cast<double>(k) + uniform_open01(rng)) / n_d);
      }
      invert_cdf(w, u, out);
      break;
    }
    case ResamplingMethod::kSystematic: {
      const double offset = uniform_open01(rng);
      for (std::size_t k = 0; k < n; ++k) u.push_back((static_cast<double>(k) + offset) / n_d);
      invert_cdf(w, u, out);
      break;
    }
    case ResamplingMethod::kResidual: {
      std::vector<double> residual(n);
      std::size_t deterministic = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const double copies = std::floor(n_d * w[i]);
        for (std::size_t c = 0; c < static_cast<std::size_t>(copies); ++c) out.push_back(i);
        deterministic += static_cast<std::size_t>(copies);
        residual[i] = n_d * w[i] - copies;
      }
      const std::size_t remaining = n - std::min(deterministic, n);
      if (remaining > 0) {
        double residual_sum = 0.0;
        for (const double r : residual) residual_sum += r;
        if (residual_sum > 0.0) {
          for (double& r : residual) r /= residual_sum;
        } else {
          std::fill(residual.begin(), residual.end(), 1.0 / n_d);
        }
        for (std::size_t k = 0; k < remaining; ++k) u.push_back(uniform_open01(rng));
        std::sort(u.begin(), u.end());
        invert_cdf(residual, u, out);
      }
      out.resize(n);  // rounding can never add copies beyond n, but keep the contract exact
      std::sort(out.begin(), out.end());
      break;
    }
  }
  return out;
}

}  // namespace losmimo::localization
