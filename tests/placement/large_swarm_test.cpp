// Large swarms (docs/performance.md): the exact lattice URA on 8 x 8 and 16 x 16 BS
// arrays, the GD escape options for large arrays, and that every default keeps the paper-setup
// behaviour.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/gd.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/placement/settings.h"
#include "losmimo/placement/ura.h"
#include "support/scenarios.h"

namespace lp = losmimo::placement;

namespace {
constexpr double kTargetIcn = 0.95;

lp::Scenario square_array(int side) { return losmimo::test_support::square_array_scenario(side); }

struct UraOutcome {
  double icn = 0.0;
  double travel_m = 0.0;  // mean per UAV
};

UraOutcome run_ura(const lp::Scenario& s, lp::UraVariant variant, std::uint64_t seed) {
  const lp::ChannelModel model(s);
  std::mt19937_64 rng(seed);
  lp::Swarm swarm(model, lp::random_start_positions_m(s, rng), {}, seed);
  lp::UraPlanner ura(s, variant);
  ura.start(swarm);
  ura.iterate(swarm, 1);
  // Independent check: the SVD of the full channel at the final positions.
  return {lp::inverse_condition_number(model.matrix(swarm.true_positions_m())), swarm.placement_distance_m().mean()};
}
}  // namespace

TEST(GdOptions, Defaults_AreThePaperSetupValues) {
  // The experiment's outputs are compared byte for byte: the defaults must not move.
  const lp::GdOptions o;
  EXPECT_EQ(o.step, 0.05);
  EXPECT_EQ(o.decay, 0.999);
  EXPECT_EQ(o.max_move_m, 0.5);
  EXPECT_TRUE(o.backtracking);
  EXPECT_EQ(o.max_halvings, 6);
  EXPECT_TRUE(o.escape);
  EXPECT_EQ(o.stall_window, 20);
  EXPECT_EQ(o.stall_min_decrease, 0.01);
  EXPECT_EQ(o.escape_half_grid, 4);  // the 9 x 9 grid, spacing period / 8
  EXPECT_EQ(o.escape_uavs, 1);
  EXPECT_EQ(o.depth_step_gain, 1.0);
  EXPECT_EQ(lp::kDefaultLateralHalfGrid, 4);
}

TEST(LateralSearch, HalfGrid_SetsTheGridSpacingAndReach) {
  // GIVEN: a UAV of the 16 x 16 setup at a random start, and one lateral period
  const lp::Scenario s = square_array(16);
  const lp::ChannelModel model(s);
  std::mt19937_64 rng(3);
  const lp::Swarm swarm(model, lp::random_start_positions_m(s, rng), {}, 3);
  const lp::UavObjective view(swarm.channel(), 0);
  const Eigen::Vector3d q = swarm.true_positions_m().col(0);
  const double period = lp::lateral_period_m(s.wavelength_m(), q.x(), s.bs_spacing_m);
  for (const int h : {4, 8}) {
    const lp::LateralSearch r = lp::search_lateral_period(view, q, period, h);
    // THEN: the best offset is a grid point (multiple of period / 2h) within half a period
    const double spacing = period / (2 * h);
    EXPECT_EQ(r.offset_m.x(), 0.0);
    EXPECT_LE(r.offset_m.tail<2>().cwiseAbs().maxCoeff(), 0.5 * period + 1e-9);
    for (int k = 1; k < 3; ++k) {
      const double steps = r.offset_m(k) / spacing;
      EXPECT_NEAR(steps, std::round(steps), 1e-9) << "h " << h;
    }
    EXPECT_LE(r.best_objective, r.objective_at_start);
  }
  // The finer grid contains the coarse one, so it finds at least as low an objective.
  EXPECT_LE(lp::search_lateral_period(view, q, period, 8).best_objective,
            lp::search_lateral_period(view, q, period).best_objective);
}

TEST(GdOptions, EscapeOptions_OutOfRange_AreRejectedNamingTheField) {
  lp::GdOptions o;
  o.escape_half_grid = 0;
  EXPECT_THROW(lp::validate(o), std::invalid_argument);
  o = {};
  o.depth_step_gain = 0.0;
  EXPECT_THROW(lp::validate(o), std::invalid_argument);
  o = {};
  o.escape_uavs = 0;
  try {
    lp::validate(o);
    FAIL() << "escape_uavs = 0 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("gd.escape_uavs = 0"), std::string::npos) << e.what();
  }
}

TEST(Settings, EscapeKeys_AreReadValidatedAndWrittenOnlyWhenSet) {
  // Defaults: the INI text has no new keys (datasets/configs/paper.ini stays as it is).
  const std::string defaults = lp::to_ini(lp::load_placement_settings(losmimo::common::IniConfig()));
  EXPECT_EQ(defaults.find("escape_half_grid"), std::string::npos);
  EXPECT_EQ(defaults.find("escape_uavs"), std::string::npos);
  EXPECT_EQ(defaults.find("depth_step_gain"), std::string::npos);

  const lp::PlacementSettings set = lp::load_placement_settings(losmimo::common::IniConfig::from_string(
      "[gd]\nescape_half_grid = 8\nescape_uavs = 32\ndepth_step_gain = 100\n", "big.ini"));
  EXPECT_EQ(set.gd.escape_half_grid, 8);
  EXPECT_EQ(set.gd.escape_uavs, 32);
  EXPECT_EQ(set.gd.depth_step_gain, 100.0);
  const std::string text = lp::to_ini(set);
  const lp::PlacementSettings again =
      lp::load_placement_settings(losmimo::common::IniConfig::from_string(text, "again"));
  EXPECT_EQ(again.gd.escape_half_grid, 8);
  EXPECT_EQ(again.gd.escape_uavs, 32);
  EXPECT_EQ(again.gd.depth_step_gain, 100.0);
  EXPECT_EQ(lp::to_ini(again), text);

  try {
    lp::load_placement_settings(losmimo::common::IniConfig::from_string("[gd]\nescape_uavs = 0\n", "bad.ini"));
    FAIL() << "escape_uavs = 0 accepted";
  } catch (const losmimo::common::InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("escape_uavs"), std::string::npos) << msg;
    EXPECT_NE(msg.find('0'), std::string::npos) << msg;
  }
  try {
    lp::load_placement_settings(losmimo::common::IniConfig::from_string("[gd]\ndepth_step_gain = -2\n", "bad.ini"));
    FAIL() << "depth_step_gain = -2 accepted";
  } catch (const losmimo::common::InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("bad.ini"), std::string::npos) << msg;
    EXPECT_NE(msg.find("[gd] depth_step_gain: -2: must be > 0"), std::string::npos) << msg;
  }
}

TEST(UraLatticeExact, DepthBand_FollowsTheFresnelTolerance) {
  // b = phi_tol lambda R^2 / (pi rho_max^2): 11.4 m for 16 x 16, 52 m for 8 x 8 at 1 km, 60 GHz.
  EXPECT_NEAR(lp::lattice_depth_band_m(square_array(16)), 11.3, 0.2);
  EXPECT_NEAR(lp::lattice_depth_band_m(square_array(8)), 52.0, 0.5);
  EXPECT_GT(lp::lattice_depth_band_m(square_array(4)), 250.0);
}

TEST(UraLatticeExact, Array8x8_64Uavs_ReachesTheTargetInOneIteration) {
  const lp::Scenario s = square_array(8);
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const UraOutcome exact = run_ura(s, lp::UraVariant::kLatticeExact, seed);
    const UraOutcome rigid = run_ura(s, lp::UraVariant::kRigid, seed);
    EXPECT_GE(exact.icn, kTargetIcn) << "seed " << seed;
    EXPECT_LT(exact.travel_m, 0.5 * rigid.travel_m) << "seed " << seed;
  }
}

TEST(UraLatticeExact, Array16x16_256Uavs_ReachesTheTargetWhereTheParaxialLatticeDoesNot) {
  // GIVEN: the documented 256-UAV case (BS 16 x 16, 60 GHz, 0.25 m, 50 m cube at 1 km)
  const lp::Scenario s = square_array(16);
  const UraOutcome paraxial = run_ura(s, lp::UraVariant::kLattice, 7);
  const UraOutcome exact = run_ura(s, lp::UraVariant::kLatticeExact, 7);
  // THEN: the paraxial lattice stops short of 0.95; the exact one passes it, still travelling
  // far less than the rigid URA (18 m per UAV)
  EXPECT_LT(paraxial.icn, kTargetIcn);
  EXPECT_GE(exact.icn, kTargetIcn);
  EXPECT_LT(exact.travel_m, 8.0);
}

TEST(GradientDescent, DepthStepGain_ScalesOnlyTheDepthComponentOfTheStep) {
  // GIVEN: no cap and no backtracking, so the step is -b grad f / Nr, then the gain
  const lp::Scenario s = square_array(8);
  const lp::ChannelModel model(s);
  std::mt19937_64 rng(5);
  const lp::Swarm swarm(model, lp::random_start_positions_m(s, rng), {}, 5);
  lp::GdOptions plain;
  plain.backtracking = false;
  plain.max_move_m = 1e9;
  lp::GdOptions gained = plain;
  gained.depth_step_gain = 1000.0;
  const lp::GradientDescentPlanner a(s, plain);
  const lp::GradientDescentPlanner b(s, gained);
  for (int m = 0; m < s.num_uavs; m += 7) {
    const Eigen::Vector3d q = swarm.true_positions_m().col(m);
    const Eigen::Vector3d ra = a.plan_move(swarm, m, q, 1);
    const Eigen::Vector3d rb = b.plan_move(swarm, m, q, 1);
    // THEN: depth x1000, lateral unchanged
    EXPECT_DOUBLE_EQ(rb.x(), 1000.0 * ra.x()) << "uav " << m;
    EXPECT_EQ(rb.y(), ra.y());
    EXPECT_EQ(rb.z(), ra.z());
    EXPECT_NE(ra.x(), 0.0);
  }
}

TEST(GradientDescent, DepthStepGain_KeepsLoweringTheObjectiveWhereThePaperStepStalls) {
  // GIVEN: 64 UAVs (BS 8 x 8) on the paraxial lattice, whose remaining error is the Fresnel
  // phase of UAVs at different depths: f varies ~x / rho = 1000 times more slowly along the link
  // than across it, so the paper's step stops moving in depth.
  const lp::Scenario s = square_array(8);
  const lp::ChannelModel model(s);
  constexpr int kFirst = 20;
  constexpr int kLast = 60;
  const auto relative_decrease = [&](double gain, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    lp::Swarm swarm(model, lp::random_start_positions_m(s, rng), {}, seed);
    lp::UraPlanner lattice(s, lp::UraVariant::kLattice);
    lattice.start(swarm);
    lattice.iterate(swarm, 1);
    lp::GdOptions o;
    o.depth_step_gain = gain;
    lp::GradientDescentPlanner gd(s, o);
    gd.start(swarm);
    double f_first = 0.0;
    for (int i = 1; i <= kLast; ++i) {
      gd.iterate(swarm, i);
      if (i == kFirst) f_first = swarm.channel().objective();
    }
    return 1.0 - swarm.channel().objective() / f_first;
  };
  for (std::uint64_t seed = 1; seed <= 2; ++seed) {
    // THEN: from iteration 20 to 60 f is flat with the paper's step, still falling with the gain
    EXPECT_LT(relative_decrease(1.0, seed), 0.005) << "seed " << seed;
    EXPECT_GT(relative_decrease(1e4, seed), 0.03) << "seed " << seed;
  }
}
