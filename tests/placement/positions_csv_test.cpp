// Positions files: a plain x,y,z list and a table of swarms (losmimo-experiment's positions.csv)
// read one swarm at a time by a selection of its columns.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/positions_csv.h"

namespace lp = losmimo::placement;

namespace {

// Two trials, two stages, two UAVs, as the experiment writes them.
const char* const kTable =
    "sweep,value,algorithm,trial,uav,stage,x,y,z\n"
    "sigma_loc_m,0,gd,0,1,start,1000,1,2\n"
    "sigma_loc_m,0,gd,0,2,start,1001,3,4\n"
    "sigma_loc_m,0,gd,0,1,final,1002,5,6\n"
    "sigma_loc_m,0,gd,0,2,final,1003,7,8\n"
    "sigma_loc_m,0,gd,1,1,final,1004,9,10\n"
    "sigma_loc_m,0,gd,1,2,final,1005,11,12\n";

Eigen::Matrix3Xd parse(const std::string& text, const lp::PositionsSelection& selection) {
  std::istringstream in(text);
  return lp::parse_positions_csv(in, "positions.csv", 65536, selection);
}

std::string error_of(const std::string& text, const lp::PositionsSelection& selection) {
  try {
    parse(text, selection);
  } catch (const losmimo::common::InputError& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

TEST(PositionsCsv, ExperimentTable_OneSwarmBySelection_InFileOrder) {
  const Eigen::Matrix3Xd q = parse(kTable, {{"trial", "0"}, {"stage", "final"}});
  ASSERT_EQ(q.cols(), 2);
  EXPECT_EQ(q.col(0), Eigen::Vector3d(1002, 5, 6));
  EXPECT_EQ(q.col(1), Eigen::Vector3d(1003, 7, 8));
  // A value matches as the same number too ("0.0" is trial 0's value 0).
  EXPECT_EQ(parse(kTable, {{"trial", "1"}, {"value", "0.0"}}).col(1), Eigen::Vector3d(1005, 11, 12));
}

TEST(PositionsCsv, ExperimentTable_AmbiguousSelection_ListsTheValuesToChooseFrom) {
  const std::string e = error_of(kTable, {{"stage", "final"}});
  EXPECT_NE(e.find("holds several swarms"), std::string::npos) << e;
  EXPECT_NE(e.find("trial: 0, 1"), std::string::npos) << e;
  EXPECT_EQ(e.find("stage:"), std::string::npos) << e;  // fixed by the selection
  EXPECT_NE(error_of(kTable, {}).find("stage: start, final"), std::string::npos);
}

TEST(PositionsCsv, SelectionNamingNothing_IsRefusedNamingTheColumns) {
  EXPECT_NE(error_of(kTable, {{"trail", "0"}}).find("no column 'trail'"), std::string::npos);
  EXPECT_NE(error_of(kTable, {{"trail", "0"}}).find("sweep, value, algorithm, trial, uav, stage, x, y, z"),
            std::string::npos);
  EXPECT_NE(error_of(kTable, {{"trial", "7"}, {"stage", "final"}}).find("no positions with trial=7, stage=final"),
            std::string::npos);
  // A plain file has no column to select by.
  const std::string plain = error_of("1000,0,0\n1001,1,1\n", {{"trial", "0"}});
  EXPECT_NE(plain.find("no column 'trial'"), std::string::npos) << plain;
  EXPECT_NE(plain.find("columns: x, y, z"), std::string::npos) << plain;
}

TEST(PositionsCsv, PlainFile_ReadsAsBefore_WithOrWithoutItsHeader) {
  EXPECT_EQ(parse("x,y,z\n1000,1,2\n", {}).col(0), Eigen::Vector3d(1000, 1, 2));
  EXPECT_EQ(parse("# c\n1000,1,2\n1001,3,4\n", {}).cols(), 2);
  // A row of the wrong width names the columns it expected.
  EXPECT_NE(error_of(kTable + std::string("sigma_loc_m,0,gd\n"), {{"trial", "1"}}).find("expected 9 fields"),
            std::string::npos);
}
