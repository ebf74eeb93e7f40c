// Records carry their own proof (experiment/records.h): one record missing, duplicated or
// altered in a shard's records.csv or a checkpoint's records.partial is refused by merge and
// --resume with exit code 2, naming the folder (file, line) and the record.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "losmimo/apps/lib/experiment_app.h"
#include "in_process.h"
#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/hash.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/experiment/records.h"
#include "support/files.h"

namespace losmimo::experiment {
namespace {

namespace fs = std::filesystem;
using test_support::read_file;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l + "\n");
  return out;
}
std::string join(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += l;
  return s;
}

TrialRecord record(int trial, const std::string& algorithm, double icn) {
  TrialRecord r;
  r.sweep = "sigma_loc_m";
  r.algorithm = algorithm;
  r.trial = trial;
  r.status = "converged";
  r.final_icn = icn;
  r.start_m = Eigen::Matrix3Xd::Constant(3, 2, 1.5);
  r.final_m = Eigen::Matrix3Xd::Constant(3, 2, 2.5);
  return r;
}

// Two points, two trials of two algorithms each; a shard's file (closed by its e line).
std::string shard_text() {
  RecordsWriter w;
  std::string t = w.header({kRecordsKindShard, 0, 1, 0x1234});
  for (int p = 0; p < 2; ++p) {
    t += w.point(p, {record(0, "gd", 0.9 + p), record(0, "bf", 0.8), record(1, "gd", 0.7), record(1, "bf", 0.6)});
  }
  return t + w.end();
}

std::string error_of(const std::string& text, RecordsMode mode) {
  std::istringstream in(text);
  try {
    read_records(in, "s0/records.csv", mode);
  } catch (const common::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(RecordsProof, IntactFile_ReadsBackEveryPoint) {
  std::istringstream in(shard_text());
  const RecordLines r = read_records(in, "s0/records.csv", RecordsMode::kComplete);
  EXPECT_EQ(r.points.size(), 2u);
  EXPECT_EQ(r.records, 8);
  EXPECT_EQ(r.header.config_digest, 0x1234u);
}

TEST(RecordsProof, RecordMissing_IsRefusedNamingFileLineAndPoint) {
  std::vector<std::string> l = lines_of(shard_text());
  l.erase(l.begin() + 3);  // magic, h, r(0,gd), [r(0,bf)] ...
  const std::string e = error_of(join(l), RecordsMode::kComplete);
  EXPECT_NE(e.find("s0/records.csv:6: point 0 has 3 records where its d line says 4 (a record missing)"),
            std::string::npos)
      << e;
}

TEST(RecordsProof, RecordDuplicated_IsRefusedNamingTheRecordAndBothLines) {
  std::vector<std::string> l = lines_of(shard_text());
  l.insert(l.begin() + 3, l[2]);
  const std::string e = error_of(join(l), RecordsMode::kComplete);
  EXPECT_NE(e.find("s0/records.csv:4: record (point 0, trial 0, gd) appears twice (also line 3)"), std::string::npos)
      << e;
}

TEST(RecordsProof, ValueAltered_IsRefusedNamingTheRecord) {
  std::vector<std::string> l = lines_of(shard_text());
  const std::size_t at = l[4].find(",0.69999999999999996,");
  ASSERT_NE(at, std::string::npos) << l[4];
  l[4].replace(at, 21, ",0.12345678900000000,");
  const std::string e = error_of(join(l), RecordsMode::kComplete);
  EXPECT_NE(e.find("s0/records.csv:5: record (point 0, trial 1, gd) was altered"), std::string::npos) << e;
}

TEST(RecordsProof, ValueAlteredWithItsLineDigestRecomputed_IsCaughtByThePointsDigest) {
  std::vector<std::string> l = lines_of(shard_text());
  std::string body = l[4].substr(0, l[4].rfind(','));
  body.replace(body.find(",0.69999999999999996,"), 21, ",0.12345678900000000,");
  l[4] = body + "," + common::format_hex64(common::fnv1a64(body)) + "\n";
  const std::string e = error_of(join(l), RecordsMode::kComplete);
  EXPECT_NE(e.find("s0/records.csv:7: point 0: the digest of the file up to here differs"), std::string::npos) << e;
}

TEST(RecordsProof, ShardFileCutAtAPoint_IsRefusedForWantOfItsEndLine) {
  std::vector<std::string> l = lines_of(shard_text());
  l.resize(7);  // through point 0's d line
  const std::string e = error_of(join(l), RecordsMode::kComplete);
  EXPECT_NE(e.find("no e line: the file is cut short (1 points, 4 records verified)"), std::string::npos) << e;
}

TEST(RecordsProof, CheckpointCutMidLine_KeepsTheFinishedPoints) {
  RecordsWriter w;
  std::string c = w.header({kRecordsKindRun, 0, 1, 0x1234});
  c += w.point(0, {record(0, "gd", 0.9), record(0, "bf", 0.8), record(1, "gd", 0.7), record(1, "bf", 0.6)});
  const std::string p1 = w.point(1, {record(0, "gd", 1.9), record(0, "bf", 0.8)});
  c += p1.substr(0, p1.size() - 60);  // an interrupted write
  std::istringstream in(c);
  const RecordLines r = read_records(in, "r.partial", RecordsMode::kCheckpoint);
  EXPECT_EQ(r.points.size(), 1u);
  EXPECT_EQ(r.records, 4);
}

// ---- the apps ----

apps::ExperimentOptions tiny(const fs::path& out, const std::string& shard) {
  apps::ExperimentOptions o;
  o.out_dir = out.string();
  o.threads = 1;
  o.shard = shard;
  o.overrides = {"experiment.trials=2",
                 "experiment.sweeps=sigma_loc_m",
                 "experiment.sigma_loc_values_m=0, 0.1",
                 "experiment.algorithms=random, gd",
                 "experiment.plots=false",
                 "placement.max_iterations=20"};
  return o;
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

// The r line with its status field (the 9th) replaced.
std::string with_status(const std::string& line, const std::string& status) {
  std::size_t at = 0;
  for (int i = 0; i < 8; ++i) at = line.find(',', at) + 1;
  return line.substr(0, at) + status + line.substr(line.find(',', at));
}

// Rewrites the manifest's entry for `file` as if the run had written it so: what is left to
// catch a change is then the records' own proof.
void reseal(const fs::path& dir, const std::string& file) {
  const std::string bytes = read_file(dir / file);
  std::vector<std::string> l = lines_of(read_file(dir / "losmimo-run.ini"));
  for (std::string& line : l) {
    const std::size_t at = line.find(" = " + file + " ");
    if (at != std::string::npos) {
      line = line.substr(0, at) + " = " + file + " " + std::to_string(bytes.size()) + " " +
             common::format_hex64(common::fnv1a64(bytes)) + "\n";
    }
  }
  write(dir / "losmimo-run.ini", join(l));
}

class RecordsProofApps : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::path(::testing::TempDir()) / ("losmimo_proof_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    ASSERT_EQ(test_support::run_experiment(tiny(root_ / "s0", "0/2")), 0);
    ASSERT_EQ(test_support::run_experiment(tiny(root_ / "s1", "1/2")), 0);
  }
  void TearDown() override { fs::remove_all(root_); }
  fs::path root_;
};

TEST_F(RecordsProofApps, MergeOfAShardWithARecordDeleted_Exits2NamingFolderAndRecord) {
  std::vector<std::string> l = lines_of(read_file(root_ / "s1" / "records.csv"));
  l.erase(l.begin() + 3);
  write(root_ / "s1" / "records.csv", join(l));
  std::string err;
  // The manifest sees the file changed...
  EXPECT_EQ(test_support::run_merge({root_ / "s0", root_ / "s1"}, root_ / "m", &err), 2);
  EXPECT_NE(err.find((root_ / "s1" / "records.csv").string() + ": changed since the run wrote it"), std::string::npos)
      << err;
  // ...and with the manifest made to agree, the records themselves.
  reseal(root_ / "s1", "records.csv");
  EXPECT_EQ(test_support::run_merge({root_ / "s0", root_ / "s1"}, root_ / "m", &err), 2);
  EXPECT_NE(err.find((root_ / "s1" / "records.csv").string() + ":"), std::string::npos) << err;
  EXPECT_NE(err.find("a record missing"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(root_ / "m"));
}

TEST_F(RecordsProofApps, MergeOfAShardWithARecordDuplicatedOrAltered_Exits2NamingTheRecord) {
  const std::string original = read_file(root_ / "s0" / "records.csv");
  std::vector<std::string> l = lines_of(original);
  l.insert(l.begin() + 3, l[2]);
  write(root_ / "s0" / "records.csv", join(l));
  reseal(root_ / "s0", "records.csv");
  std::string err;
  EXPECT_EQ(test_support::run_merge({root_ / "s0", root_ / "s1"}, root_ / "m", &err), 2);
  EXPECT_NE(err.find("records.csv:4: record (point 0, trial 0, random) appears twice (also line 3)"), std::string::npos)
      << err;

  l = lines_of(original);
  l[2] = with_status(l[2], "tampered");
  write(root_ / "s0" / "records.csv", join(l));
  reseal(root_ / "s0", "records.csv");
  EXPECT_EQ(test_support::run_merge({root_ / "s0", root_ / "s1"}, root_ / "m", &err), 2);
  EXPECT_NE(err.find("records.csv:3: record (point 0, trial 0, random) was altered"), std::string::npos) << err;
}

TEST_F(RecordsProofApps, ResumeOfACheckpointWithARecordAltered_Exits2NamingTheRecord) {
  // GIVEN: shard 0's finished records as an interrupted run's checkpoint (no e line).
  const fs::path staging = root_ / "c.partial";
  fs::create_directories(staging);
  fs::copy_file(root_ / "s0" / "config.ini", staging / "config.ini");
  std::vector<std::string> l = lines_of(read_file(root_ / "s0" / "records.csv"));
  l.pop_back();
  write(staging / "records.partial", join(l));
  // WHEN: resumed as it is: it finishes shard 0, the same as the uninterrupted one.
  apps::ExperimentOptions o = tiny(root_ / "c", "0/2");
  o.out_dir.reset();
  o.shard.reset();
  o.resume_dir = (root_ / "c").string();
  std::string err;
  ASSERT_EQ(test_support::run_experiment(o, &err), 0) << err;
  EXPECT_EQ(read_file(root_ / "c" / "records.csv"), read_file(root_ / "s0" / "records.csv"));
  // WHEN: a value in a finished point is changed.
  fs::remove_all(root_ / "c");
  fs::create_directories(staging);
  fs::copy_file(root_ / "s0" / "config.ini", staging / "config.ini");
  l[2] = with_status(l[2], "tampered");
  write(staging / "records.partial", join(l));
  // THEN
  EXPECT_EQ(test_support::run_experiment(o, &err), 2);
  EXPECT_NE(err.find((staging / "records.partial").string() + ":3: record (point 0, trial 0, random) was altered"),
            std::string::npos)
      << err;
  EXPECT_FALSE(fs::exists(root_ / "c"));
}

}  // namespace
}  // namespace losmimo::experiment
