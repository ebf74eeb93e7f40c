#pragma once
// Shared fixtures of the closed-loop tests: the paper scenario's settings, seeded start
// positions, the matched nominal config, and an observer that keeps what the loop reported.
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "losmimo/fusion/closed_loop.h"

namespace losmimo::test_support {

inline constexpr double kSigmaAct_m = 0.02;  // actuation error of every closed-loop test

// The paper scenario (16 UAVs, 4 x 4 BS, 1 km) with actuation error kSigmaAct_m.
inline placement::PlacementSettings paper_settings(int max_iterations) {
  placement::PlacementSettings s;
  s.errors.sigma_act_m = kSigmaAct_m;
  s.run.max_iterations = max_iterations;
  return s;
}

inline Eigen::Matrix3Xd start_positions(const placement::Scenario& scenario, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  return placement::random_start_positions_m(scenario, rng);
}

// The default beacon, dead reckoning and filter noise, the filter matched to the truth.
inline fusion::ClosedLoopConfig nominal_config(const placement::Scenario& scenario) {
  return fusion::matched_closed_loop_config(localization::SimulatorConfig{}, scenario);
}

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Keeps what the observer sees: every epoch, and the true positions after every iteration.
struct LoopRecorder : fusion::ClosedLoopObserver {
  std::vector<fusion::EpochObservation> epochs;
  std::map<int, Eigen::Matrix3Xd> positions_after;  // iteration -> true positions
  void on_epoch(const fusion::EpochObservation& e) override { epochs.push_back(e); }
  void on_iteration_end(int iteration, const placement::Swarm& swarm) override {
    positions_after[iteration] = swarm.true_positions_m();
  }
};

}  // namespace losmimo::test_support
