#include "losmimo/localization/pose/landmark_filter.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>

#include "losmimo/localization/range_az_el.h"

namespace losmimo::localization {

namespace {

void require(bool ok, const std::string& field, double value, const char* rule) {
  if (ok) return;
  std::ostringstream msg;
  msg << field << " = " << value << ": " << rule;
  throw std::invalid_argument(msg.str());
}

// A reading screened for geometry against the predicted mean: its prediction, Jacobian and S.
struct Candidate {
  double d2 = 0.0;
  std::size_t scan = 0, reading = 0;
  std::int32_t id = -1;
};

}  // namespace

void validate(const LandmarkFilterConfig& c) {
  for (int i = 0; i < 3; ++i) {
    require(std::isfinite(c.sigma(i)) && c.sigma(i) > 0.0, "sigma(" + std::to_string(i) + ")", c.sigma(i),
            "must be > 0");
    require(std::isfinite(c.min_sigma(i)) && c.min_sigma(i) > 0.0, "min_sigma(" + std::to_string(i) + ")",
            c.min_sigma(i), "must be > 0");
  }
  for (int i = 0; i < 6; ++i) {
    require(std::isfinite(c.min_odometry_sigma(i)) && c.min_odometry_sigma(i) > 0.0,
            "min_odometry_sigma(" + std::to_string(i) + ")", c.min_odometry_sigma(i), "must be > 0");
  }
  require(std::isfinite(c.gate_chi2) && c.gate_chi2 > 0.0, "gate_chi2", c.gate_chi2, "must be > 0");
  require(c.num_particles >= 10, "num_particles", c.num_particles, "must be >= 10");
  require(c.ess_threshold > 0.0 && c.ess_threshold <= 1.0, "ess_threshold", c.ess_threshold, "must be in (0, 1]");
}

Eigen::Vector3d reading_sigma(const LandmarkFilterConfig& config, const BearingScan& scan) {
  Eigen::Vector3d s = config.sigma;
  for (int i = 0; i < 3; ++i) {
    if (config.use_scan_sigma && std::isfinite(scan.sigma(i)) && scan.sigma(i) > 0.0) s(i) = scan.sigma(i);
  }
  return s.cwiseMax(config.min_sigma);
}

Matrix6d odometry_noise(const LandmarkFilterConfig& config, const Pose6& mean, const OdometryIncrement6& u) {
  Matrix6d J_u;
  compose_pose6(mean, u.delta, nullptr, &J_u);
  const Matrix6d sigma_u = u.cov + Matrix6d(config.min_odometry_sigma.cwiseAbs2().asDiagonal());
  return J_u * sigma_u * J_u.transpose();
}

void make_planar(LandmarkBelief& belief) {
  for (const int i : {kP6Z, kP6Pitch, kP6Roll}) {
    belief.mean(i) = 0.0;
    belief.cov.row(i).setZero();
    belief.cov.col(i).setZero();
  }
}

std::vector<AssociatedReading> associate(const LandmarkFilterConfig& config, const BeaconMap& landmarks,
                                         const std::vector<BearingScan>& scans, const LandmarkBelief& predicted,
                                         LandmarkCounters& counters) {
  std::vector<AssociatedReading> out;
  // d^2 of a reading against a landmark; nullopt-like negative for degenerate geometry.
  const auto mahalanobis = [&](const BearingScan& scan, const BearingReading& r, const Eigen::Vector3d& L,
                               const Eigen::Vector3d& sigma, double& nis, double& range_y) {
    const Eigen::Vector3d p = landmark_in_sensor(predicted.mean, scan.sensor_on_robot, L);
    if (std::hypot(p.x(), p.y()) < kMinLandmarkRho_m) return -1.0;
    Matrix36d H;
    const Eigen::Vector3d h = landmark_predict(predicted.mean, scan.sensor_on_robot, L, &H);
    const Eigen::Vector3d y = range_az_el_innovation(r.z, h);
    const Eigen::Matrix3d S = H * predicted.cov * H.transpose() + Eigen::Matrix3d(sigma.cwiseAbs2().asDiagonal());
    nis = y.dot(S.ldlt().solve(y));
    range_y = y(0);
    return nis;
  };
  const auto take = [&](const BearingScan& scan, const BearingReading& r, std::int32_t id, const Eigen::Vector3d& sigma,
                        double nis, double range_y) {
    out.push_back({id, *landmarks.find(id), scan.sensor_on_robot, r.z, sigma});
    ++counters.fused;
    counters.nis_sum += nis;
    counters.innovation_sum_sq += range_y * range_y;
  };
  for (std::size_t si = 0; si < scans.size(); ++si) {
    const BearingScan& scan = scans[si];
    const Eigen::Vector3d sigma = reading_sigma(config, scan);
    std::vector<Candidate> candidates;
    std::vector<int> in_gate(scan.readings.size(), 0);
    for (std::size_t ri = 0; ri < scan.readings.size(); ++ri) {
      const BearingReading& r = scan.readings[ri];
      ++counters.readings;
      double nis = 0.0, range_y = 0.0;
      if (r.landmark_id >= 0) {  // associated by its ID
        const Eigen::Vector3d* L = landmarks.find(r.landmark_id);
        if (!L) {
          ++counters.unknown_id;
        } else if (mahalanobis(scan, r, *L, sigma, nis, range_y) < 0.0) {
          ++counters.degenerate;
        } else {
          take(scan, r, r.landmark_id, sigma, nis, range_y);
        }
        continue;
      }
      for (const auto& [id, L] : landmarks.beacons()) {
        const double d2 = mahalanobis(scan, r, L, sigma, nis, range_y);
        if (d2 >= 0.0 && d2 <= config.gate_chi2) {
          candidates.push_back({d2, si, ri, id});
          ++in_gate[ri];
        }
      }
    }
    // Global nearest neighbour: pairs by increasing d^2, one-to-one within the scan.
    std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
      return std::tie(a.d2, a.reading, a.id) < std::tie(b.d2, b.reading, b.id);
    });
    std::vector<bool> reading_taken(scan.readings.size(), false);
    std::vector<std::int32_t> landmarks_taken;
    for (const Candidate& c : candidates) {
      if (reading_taken[c.reading] ||
          std::find(landmarks_taken.begin(), landmarks_taken.end(), c.id) != landmarks_taken.end())
        continue;
      reading_taken[c.reading] = true;
      landmarks_taken.push_back(c.id);
      double nis = 0.0, range_y = 0.0;
      mahalanobis(scan, scan.readings[c.reading], *landmarks.find(c.id), sigma, nis, range_y);
      take(scan, scan.readings[c.reading], c.id, sigma, nis, range_y);
    }
    for (std::size_t ri = 0; ri < scan.readings.size(); ++ri) {
      if (scan.readings[ri].landmark_id >= 0) continue;
      if (in_gate[ri] >= 2) ++counters.ambiguous;
      if (!reading_taken[ri]) ++counters.gated;
    }
  }
  return out;
}

std::unique_ptr<LandmarkPoseFilter> make_landmark_filter(FilterKind kind, const LandmarkFilterConfig& config,
                                                         const BeaconMap& landmarks, const LandmarkBelief& start,
                                                         std::uint64_t seed) {
  validate(config);
  if (kind == FilterKind::kEkf) return make_landmark_ekf(config, landmarks, start);
  return make_landmark_particle_filter(config, landmarks, start, seed);
}

}  // namespace losmimo::localization
