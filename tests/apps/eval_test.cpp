#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "losmimo/apps/lib/eval_app.h"

namespace {
const std::string kExamples = std::string(LOSMIMO_SOURCE_DIR) + "/datasets/examples/";

struct EvalOutcome {
  int code;
  std::string out;
  std::string err;
};

EvalOutcome eval(const std::string& positions, bool csv = true) {
  losmimo::apps::EvalOptions o;
  o.positions_path = positions;
  o.csv = csv;
  std::ostringstream out, err;
  const int code = losmimo::apps::run_eval_app(o, out, err);
  return {code, out.str(), err.str()};
}

std::string temp_file(const std::string& name, const std::string& content) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << content;
  return path;
}

double csv_value(const std::string& out, const std::string& key) {
  std::istringstream in(out);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key + ",", 0) == 0) return std::stod(line.substr(key.size() + 1));
  }
  return -1.0;
}
}  // namespace

TEST(LosmimoEval, ShippedOptimalUra_ReportsIcnOneAndMfSinr) {
  const EvalOutcome r = eval(kExamples + "ura_optimal_16.csv");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_GT(csv_value(r.out, "icn"), 0.999);
  EXPECT_NE(r.out.find("stream,sinr_nv_db,sinr_zf_db,sinr_mf_db\n1,22.04"), std::string::npos) << r.out;
  EXPECT_GT(csv_value(r.out, "sum_rate_zf_bps_hz"), 100.0);
}

TEST(LosmimoEval, ShippedRandomStart_IsIllConditioned) {
  const EvalOutcome r = eval(kExamples + "random_start_16.csv", false);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("ICN"), std::string::npos);
}

TEST(LosmimoEval, BadInputs_ExitTwoNamingTheProblem) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"/nonexistent/p.csv", {"cannot open"}},
      {temp_file("cols.csv", "x,y,z\n1000,0,0\n1000,1\n"), {"cols.csv:3", "3 fields"}},
      {temp_file("nan.csv", "1000,0,0\n1000,nan,0\n"), {"nan.csv:2", "field y"}},
      {temp_file("text.csv", "1000,0,zz\n"), {"text.csv:1", "field z"}},
      {temp_file("empty.csv", "x,y,z\n"), {"no positions"}},
      {temp_file("onbs.csv", "0,0.125,0.125\n"), {"sits on BS antenna"}},
  };
  for (const auto& [path, fragments] : cases) {
    const EvalOutcome r = eval(path);
    EXPECT_EQ(r.code, 2) << path;
    for (const auto& f : fragments) EXPECT_NE(r.err.find(f), std::string::npos) << r.err;
  }
}

TEST(LosmimoEval, FewerUavsThanAntennas_OneStreamPerUav) {
  // Three UAVs 5 m apart at 1 km: nearly orthogonal rows of a 16-antenna BS.
  const EvalOutcome r = eval(temp_file("few.csv", "1000,0,0\n1000,5,0\n1000,0,5\n"), false);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("3 UAVs < 16 BS antennas: one stream per UAV"), std::string::npos) << r.out;
  const std::string csv = eval(temp_file("few2.csv", "1000,0,0\n1000,5,0\n")).out;
  EXPECT_GT(csv_value(csv, "icn"), 0.5) << csv;
  EXPECT_EQ(csv.find("\n3,"), std::string::npos) << "two UAVs give two streams: " << csv;
}

TEST(LosmimoEval, ShippedPaperIni_IsAcceptedAsScenario) {
  losmimo::apps::EvalOptions o;
  o.positions_path = kExamples + "ura_optimal_16.csv";
  o.config_path = std::string(LOSMIMO_SOURCE_DIR) + "/datasets/configs/paper.ini";
  o.csv = true;
  std::ostringstream out, err;
  EXPECT_EQ(losmimo::apps::run_eval_app(o, out, err), 0) << err.str();
  EXPECT_GT(csv_value(out.str(), "icn"), 0.999);
}

TEST(LosmimoEval, ChannelConditions_ExitTwoNamingTheKey) {
  losmimo::apps::EvalOptions o;
  o.positions_path = kExamples + "ura_optimal_16.csv";
  o.overrides = {"channel.rician_k_db=10"};
  std::ostringstream out, err;
  EXPECT_EQ(losmimo::apps::run_eval_app(o, out, err), 2);
  EXPECT_NE(err.str().find("[channel] rician_k_db: 10 is not supported by losmimo-eval"), std::string::npos)
      << err.str();
}

TEST(LosmimoEval, BadConfigValue_ExitTwo) {
  losmimo::apps::EvalOptions o;
  o.positions_path = kExamples + "ura_optimal_16.csv";
  o.overrides = {"scenario.snr_db=inf"};
  std::ostringstream out, err;
  EXPECT_EQ(losmimo::apps::run_eval_app(o, out, err), 2);
  EXPECT_NE(err.str().find("snr_db"), std::string::npos) << err.str();
}
