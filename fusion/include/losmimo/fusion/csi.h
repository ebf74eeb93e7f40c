#pragma once
// The CSI a UAV measures during placement: its own channel row, up to a common phase.
//
//   y_k = e^{j phi} x_k(q) + n_k,   k = 1..Nt,   n_k ~ CN(0, noise_variance)
//
// x = placement::ChannelModel::row(q) (normalised: far-field entries are unit modulus),
// phi is the receiver's oscillator offset (unknown, uniform in [-pi, pi) for every measurement),
// noise_variance = Scenario::noise_variance() = 1 / SNR in the same units.
//
// Phase model used by the refinement. With d_k = |q - p_k| and the virtual reference antenna at
// the array centre,
//   arg x_k(q) = -kappa d_k = -kappa |q| - kappa delta_k(q),
//   delta_k(q) = d_k - |q| = (|p_k|^2 - 2 p_k . q) / (d_k + |q|)     (no cancellation)
// so arg y_k = psi - kappa delta_k(q) + noise, with psi = phi - kappa |q| (mod 2 pi) the one
// nuisance phase per measurement. delta_k carries the lateral position (about p_k . q / |q|:
// ~0.47 rad per metre at the outer antennas, 1 km, 60 GHz, 0.75 m aperture); depth enters only
// through |q|, which psi absorbs, so CSI alone leaves depth unobservable. Writing the nuisance as
// psi instead of phi keeps the problem well conditioned (phi and depth would be collinear).
// For unit-modulus entries the phase noise is ~N(0, noise_variance / 2) at high SNR.

#include <Eigen/Core>
#include <random>

#include "losmimo/placement/channel.h"

namespace losmimo::fusion {

struct CsiMeasurement {
  Eigen::VectorXcd y;  // length Nt, normalised units
};

// Draws one measurement of the UAV at q_true_m: uniform phi, complex Gaussian noise.
CsiMeasurement simulate_csi(const placement::ChannelModel& model, const Eigen::Vector3d& q_true_m,
                            double noise_variance, std::mt19937_64& rng);

// 1-sigma phase noise of a unit-modulus entry: sqrt(noise_variance / 2) [rad].
double csi_phase_sigma_rad(double noise_variance);

// delta_k(q) = |q - p_k| - |q| for every antenna (length Nt) [m].
Eigen::VectorXd csi_path_difference_m(const placement::ChannelModel& model, const Eigen::Vector3d& q_m);

// Maximum-likelihood psi for a known position: arg sum_k y_k exp(j kappa delta_k(q)) [rad].
double csi_reference_phase_rad(const placement::ChannelModel& model, const CsiMeasurement& csi,
                               const Eigen::Vector3d& q_m);

}  // namespace losmimo::fusion
