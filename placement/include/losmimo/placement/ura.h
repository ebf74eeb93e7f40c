#pragma once
// Uniform rectangular array (URA) baseline (paper section 4, Bohagen et al. 2007).
//
// The optimal receive URA for a BS URA with spacing d_t and n elements along an axis has, at
// depth x, spacing d_r = lambda x / (n d_t) along that axis: then H has orthogonal columns.
// Rigid variant: the URA at the start cube's centre (depth R). Each UAV gets a slot by a
// minimum-total-distance assignment (Hungarian) of its first position estimate.
// Lattice variant: orthogonality survives (in the paraxial approximation) moving a UAV along
// the link (any depth x) and shifting it laterally by whole periods lambda x / d_t, so a slot
// is a lattice of points; each UAV's cost to a slot is the distance to its nearest point at
// the UAV's own depth, which travels far less (ICN ~0.99 instead of 1: the approximation).
// Every iteration each UAV re-estimates its position and commands the move to its target
// (target - believed position), so localization and actuation errors are retried away.
// Exact lattice variant ("ura_lattice_exact"), for large arrays. The lattice above is paraxial:
// it equates the direction cosine y / |q| with y / x and ignores the BS aperture's Fresnel phase
// pi (y_t^2 + z_t^2) / (lambda |q|), which differs between UAVs at different depths and which no
// lateral shift (a linear phase across the array) can cancel. On a 16 x 16 array with 256 UAVs
// in the 50 m cube both cost ICN (0.939 instead of 0.996). This variant
// - places the lattice in direction cosines: u = u_c + u_slot + k lambda / d_t (k integer, u_c
//   the start cube centre's), at y = u |q|, z = v |q| (the row's linear phase is exact);
// - clamps each UAV's depth to R +- b with b = phi_tol lambda R^2 / (pi rho_max^2), rho_max the
//   BS corner's distance from the array centre, phi_tol = kLatticeFresnelTolerance_rad: the
//   Fresnel phase then differs by at most phi_tol from that at depth R. b is 11.4 m for 16 x 16
//   at 1 km (ICN 0.967), 52 m for 8 x 8 (no clamp in the 50 m cube), 280 m for 4 x 4.
// Needs num_uavs <= bs_rows * bs_cols. With fewer UAVs than antennas (a massive-MIMO BS) the
// slots are the same Nt-slot grid (the spacing is set by the BS's elements per axis) and the
// assignment picks which Nr slots to fill: rows at any two distinct slots are orthogonal (far
// field, paraxial), so any Nr of them give ICN ~1 over the UAV streams (metrics.h).
//
// Open choices of the paper's baseline ("an optimal URA [Bohagen]; each UAV is directed to a
// position in the URA that minimizes the total distance; ... the UAVs keep attempting to get to
// the assigned positions in subsequent iterations"), UraOptions, defaults as above:
// - spacing_multiple k: d_r = k lambda x / (n d_t); every k coprime with the array's row and
//   column counts gives orthogonal columns (Bohagen et al.), k = 1 the most compact URA;
// - depth (rigid variant): the slots at the cube centre's depth (kPlane) or each at the depth of
//   the UAV assigned to it (kOwn: no motion along the link, the same angular layout);
// - retry: kEveryIteration re-estimates and commands target - estimate every iteration; kOnce
//   commands it at iteration 1 only; kAverage commands target minus the running mean of the
//   UAV's estimates of its start, each corrected by the moves commanded since (the localization
//   error averages out, the actuation error is not seen).

#include "losmimo/placement/run.h"

namespace losmimo::placement {

enum class UraVariant { kRigid, kLattice, kLatticeExact };

enum class UraDepth { kPlane, kOwn };
enum class UraRetry { kEveryIteration, kOnce, kAverage };
std::string to_string(UraDepth depth);                    // "plane", "own"
std::string to_string(UraRetry retry);                    // "every_iteration", "once", "average"
UraDepth ura_depth_from_string(const std::string& name);  // std::invalid_argument for others
UraRetry ura_retry_from_string(const std::string& name);

struct UraOptions {
  int spacing_multiple = 1;
  UraDepth depth = UraDepth::kPlane;
  UraRetry retry = UraRetry::kEveryIteration;
};
// Throws common::FieldError naming the field (spacing_multiple in [1, 64]).
void validate(const UraOptions& options);
// Throws common::FieldError("spacing_multiple") unless it is coprime with the BS array's rows
// and columns (otherwise two slots coincide in phase and H loses rank).
void validate(const UraOptions& options, const Scenario& scenario);

// The largest Fresnel phase difference between UAVs that ura_lattice_exact's depth band allows.
inline constexpr double kLatticeFresnelTolerance_rad = 0.05;
// The half-width b (metres) of ura_lattice_exact's depth band around the cube centre.
double lattice_depth_band_m(const Scenario& scenario);

// Slot positions of the rigid URA at depth R (3 x Nt, same order as the BS antennas), spacing
// multiple k.
Eigen::Matrix3Xd optimal_ura_positions_m(const Scenario& scenario, int spacing_multiple = 1);

class UraPlanner : public Planner {
 public:
  UraPlanner(const Scenario& scenario, UraVariant variant, const UraOptions& options = {});
  std::string name() const override;
  void start(Swarm& swarm) override;
  void iterate(Swarm& swarm, int iteration) override;
  // The targets, once the UAVs have been commanded there (after the first iteration).
  std::optional<Eigen::Matrix3Xd> believed_positions() const override;

  // Targets chosen by start() (3 x Nr).
  const Eigen::Matrix3Xd& targets_m() const { return targets_m_; }
  // Nearest lattice-equivalent point of slot s to position q (lattice variants).
  Eigen::Vector3d nearest_lattice_point_m(int slot, const Eigen::Vector3d& q_m) const;

 private:
  Eigen::Vector3d nearest_exact_lattice_point_m(int slot, const Eigen::Vector3d& q_m) const;

  Scenario scenario_;
  UraVariant variant_;
  UraOptions options_;
  Eigen::Matrix3Xd targets_m_;
  bool commanded_ = false;            // iterate() has run
  Eigen::Matrix3Xd start_sum_m_;      // kAverage: sum of the start estimates
  Eigen::Matrix3Xd commanded_sum_m_;  // kAverage: sum of the moves commanded
  int estimates_ = 0;
};

}  // namespace losmimo::placement
