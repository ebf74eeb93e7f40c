// The experiment's fidelity tools: readings measured with paired runs (readings.h), the Why
// lines built from them, the milestone columns, the per-algorithm stop rules and the paths of
// the path figure. Each changes what it names and nothing else.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/experiment/engine.h"
#include "losmimo/placement/experiment/extension.h"
#include "losmimo/placement/experiment/paths.h"
#include "losmimo/placement/experiment/readings.h"

namespace le = losmimo::experiment;

namespace {
constexpr int kTrials = 3;

// A small run at the paper values' points: sigma_loc {0, 0.18}, sigma_act {0.18}.
le::ExperimentSettings small(const std::string& extra = "") {
  return le::load_experiment_settings(losmimo::common::IniConfig::from_string(
      "[experiment]\ntrials = " + std::to_string(kTrials) +
      "\nsigma_loc_values_m = 0, 0.18\nsigma_act_values_m = 0.18\nalgorithms = random, gd, bf, ura\n"
      "[placement]\nmax_iterations = 60\n" +
      extra));
}

std::string error_of(const std::string& text) {
  try {
    le::load_experiment_settings(losmimo::common::IniConfig::from_string(text, "r.ini"));
  } catch (const losmimo::common::InputError& e) {
    return e.what();
  }
  return "accepted";
}

const le::TrialRecord& record_of(const std::vector<le::TrialRecord>& records, const std::string& algorithm) {
  for (const le::TrialRecord& r : records) {
    if (r.algorithm == algorithm) return r;
  }
  throw std::logic_error("no " + algorithm);
}
}  // namespace

TEST(Readings, BadReadings_StopBeforeAnyWorkNamingTheKeyAndTheReading) {
  EXPECT_EQ(error_of("[experiment]\nreadings = a: gd.nope=1\n"),
            "r.ini:2: [experiment] readings: reading 'a': gd.nope: not a placement key (a reading sets [scenario], "
            "[errors], [placement], [gd], [bf] or [ura] keys)");
  EXPECT_EQ(
      error_of("[experiment]\nreadings = a: experiment.trials=3\n").find("not a placement key") != std::string::npos,
      true);
  EXPECT_EQ(error_of("[experiment]\nreadings = a: gd.step=-1\n"),
            "r.ini:2: [experiment] readings: reading 'a': [gd] step: -1: must be > 0");
  EXPECT_EQ(error_of("[experiment]\nreadings = a: gd.step=1 | a: bf.step=1\n"),
            "r.ini:2: [experiment] readings: reading 'a' given twice");
  EXPECT_EQ(error_of("[experiment]\nreadings = a gd.step=1\n"),
            "r.ini:2: [experiment] readings: reading 'a gd.step=1': expected name: section.key=value, ...");
  EXPECT_EQ(error_of("[experiment]\nreadings = \n"), "accepted");
}

TEST(Readings, AReadingOfBfAlone_MovesNoGdOrUraValue_AndDoesNotDependOnThreads) {
  // GIVEN a reading that changes only BF's contraction
  le::ExperimentSettings s = small("[experiment]\nreadings = bf-fixed: bf.contraction=1\nreading_trials = 3\n");
  const le::ReadingResults one = le::measure_readings(s, {}, 1);
  const le::ReadingResults two = le::measure_readings(s, {}, 2);
  ASSERT_EQ(one.readings.size(), 1u);
  ASSERT_FALSE(one.values.empty());
  bool bf_moved = false;
  for (std::size_t v = 0; v < one.values.size(); ++v) {
    const le::ReadingMeasure& m = one.measures[0][v];
    const le::ReadingMeasure& m2 = two.measures[0][v];
    EXPECT_EQ(m.value.n, m2.value.n) << v;
    if (m.value.n > 0) {
      EXPECT_EQ(m.value.mean, m2.value.mean) << v;
    }
    const std::string& a = one.values[v].algorithm;
    if (a == "gd" || a == "ura" || a == "random") {
      // THEN every other algorithm's value is the same, trial for trial
      if (m.delta.n > 0) {
        EXPECT_EQ(m.delta.mean, 0.0) << one.values[v].quantity;
      }
      EXPECT_EQ(m.value.n, m.base.n) << one.values[v].quantity;
    } else if (m.delta.n > 0 && m.delta.mean != 0.0) {
      bf_moved = true;
    }
  }
  EXPECT_TRUE(bf_moved);
  // The premise of running a [bf] reading for BF alone: the other algorithms' runs are the same.
  const le::ExperimentSettings bf_fixed = le::apply_reading(s, s.readings[0], {});
  for (int point = 0; point < 2; ++point) {
    const auto base_records = le::run_trial(s, le::kSweepSigmaLoc, point, 1);
    const auto reading_records = le::run_trial(bf_fixed, le::kSweepSigmaLoc, point, 1);
    for (const char* a : {"gd", "ura", "random"}) {
      EXPECT_EQ(record_of(base_records, a).final_m, record_of(reading_records, a).final_m) << a;
    }
    EXPECT_NE(record_of(base_records, "bf").final_m, record_of(reading_records, "bf").final_m);
  }
  // The base is this configuration's own first trials.
  const le::ReadingMeasure* gd_nv = one.find(0, 17);  // GD final NV SINR at sigma_loc 0.18
  ASSERT_NE(gd_nv, nullptr);
  ASSERT_EQ(gd_nv->base.n, kTrials);
  double sum = 0.0;
  for (int t = 0; t < kTrials; ++t) sum += record_of(le::run_trial(s, le::kSweepSigmaLoc, 1, t), "gd").sinr_nv_db;
  EXPECT_NEAR(gd_nv->base.mean, sum / kTrials, 1e-12);
}

TEST(Readings, WhyLines_NameTheReadingThatMovesTheValueOrSayTheCauseIsUnknown) {
  le::ReadingResults res;
  res.trials = 10;
  const std::vector<le::PaperValue> all = le::paper_values();
  res.values = {all[16]};  // GD NV at sigma_loc 0.18, paper 16.5
  res.value_numbers = {17};
  res.readings = {{"gd-f", {{"gd.step", "0.8"}}}, {"bf-k", {{"bf.contraction", "1"}}}};
  const auto est = [](double mean, double ci, int n) { return le::Estimate{mean, ci, n}; };
  res.measures = {{{est(16.8, 0.4, 10), est(21.3, 0.1, 10), est(-4.5, 0.3, 10)}},
                  {{est(21.3, 0.1, 10), est(21.3, 0.1, 10), est(0.0, 0.0, 10)}}};
  const std::string why = le::explain_difference(res.values[0], 17, res);
  EXPECT_EQ(why, "gd-f: gd.step=0.8: -4.50 ± 0.30 dB, to 16.80 (agrees) (paired runs, 10 trials per reading)");
  res.measures[0][0] = {est(21.0, 0.4, 10), est(21.3, 0.1, 10), est(-0.3, 0.5, 10)};  // within its CI
  EXPECT_EQ(le::explain_difference(res.values[0], 17, res),
            "cause unknown: none of the 2 readings moves it toward the paper beyond the CI of its paired "
            "difference (paired runs, 10 trials per reading)");
  EXPECT_EQ(le::explain_difference(res.values[0], 17, le::ReadingResults{}).rfind("cause unknown: no reading", 0), 0u);
}

TEST(MilestoneColumns, Off_NoExtraColumns_On_TheMilestoneIterations) {
  const le::ExperimentSettings off = small();
  EXPECT_TRUE(le::extra_metric_names(off, {}).empty());
  le::ExperimentSettings on = small("[experiment]\nmilestone_columns = true\n");
  on.sweeps.resize(1);
  on.sweeps[0].values = {0.0};
  on.trials = 1;
  on.placement.run.max_iterations = 1000;
  EXPECT_EQ(le::extra_metric_names(on, {}), (std::vector<std::string>{"iterations_to_icn050", "iterations_to_icn095"}));
  const le::ExperimentResults res = le::run_experiment(on, {}, 1);
  for (const le::TrialRecord& r : res.records) {
    ASSERT_EQ(r.extra.size(), 2u) << r.algorithm;
    if (r.icn095_iteration >= 0) {
      EXPECT_EQ(r.extra[1], r.icn095_iteration);
    } else {
      EXPECT_TRUE(std::isnan(r.extra[1]));
    }
  }
  EXPECT_EQ(record_of(res.records, "gd").extra[1], record_of(res.records, "gd").iterations);  // stops at 0.95
}

TEST(RunOverride, GdCap_ChangesGdRunsOnly) {
  const le::ExperimentSettings base = small();
  const le::ExperimentSettings capped = small("[gd]\nmax_iterations = 3\ntarget_icn = 1\n");
  const auto a = le::run_trial(base, le::kSweepSigmaAct, 0, 1);
  const auto b = le::run_trial(capped, le::kSweepSigmaAct, 0, 1);
  EXPECT_EQ(record_of(b, "gd").iterations, 3);
  EXPECT_NE(record_of(a, "gd").final_m, record_of(b, "gd").final_m);
  for (const char* other : {"bf", "ura", "random"}) {
    EXPECT_EQ(record_of(a, other).final_m, record_of(b, other).final_m) << other;
    EXPECT_EQ(record_of(a, other).iterations, record_of(b, other).iterations) << other;
  }
}

TEST(Paths, Fig1RunsRecordTheirPath_ErrorRunsGoToPathsOnly) {
  le::ExperimentSettings s = small();
  const std::vector<le::TracedRun> with = le::traced_runs(s);
  s.paths = false;
  const std::vector<le::TracedRun> without = le::traced_runs(s);
  ASSERT_EQ(without.size(), 2u);  // GD and BF, no errors
  ASSERT_EQ(with.size(), 4u);     // and both again under sigma_act 0.18
  for (std::size_t i = 0; i < 2; ++i) {
    const le::TracedRun& t = with[i];
    EXPECT_TRUE(t.fig1());
    EXPECT_TRUE(without[i].result.path.empty());
    // The same run: recording the path changes nothing else.
    EXPECT_EQ(t.result.final_m, without[i].result.final_m);
    EXPECT_EQ(t.result.trace.size(), without[i].result.trace.size());
    ASSERT_EQ(t.result.path.size(), static_cast<std::size_t>(t.result.iterations) + 1);
    EXPECT_EQ(t.result.path.front(), t.result.start_m);
    EXPECT_EQ(t.result.path.back(), t.result.final_m);
  }
  for (std::size_t i = 2; i < 4; ++i) {
    EXPECT_FALSE(with[i].fig1());
    EXPECT_EQ(with[i].sigma_act_m, 0.18);
    EXPECT_EQ(with[i].result.path.front(), with[0].result.start_m);  // the same start
  }
  std::ostringstream out;
  le::write_paths_csv(out, with);
  const std::string csv = out.str();
  std::size_t rows = 0;
  for (const le::TracedRun& t : with) rows += t.result.path.size() * 16;
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')), rows + 1);
}
