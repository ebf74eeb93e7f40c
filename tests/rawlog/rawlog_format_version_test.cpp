// The format version in the CONFIG header (format.h): version-1 logs (the shipped missions and
// tests/rawlog/data/format_v1, kept as recorded for this) still read and replay byte for byte as
// before, new logs are version 2 with the standard-type streams and replay the same, and a newer
// version is refused with a message that names it.
#include <gtest/gtest.h>

#include <sstream>

#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/serialization/CArchive.h>

#include "losmimo/apps/lib/replay_app.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/fusion/rawlog/mission/format.h"
#include "losmimo/fusion/rawlog/mission/log.h"
#include "losmimo/fusion/rawlog/mission/recorder.h"
#include "losmimo/fusion/rawlog/mission/replay.h"
#include "rawlog_test_util.h"

namespace losmimo::rawlog {
namespace {

using test_support::load_log;
using test_support::small_mission;
using test_support::source_path;
using test_support::temp_path;

const std::string& recorded_log() {
  static const std::string path = [] {
    const std::string p = temp_path("format_version.rawlog");
    record_mission(small_mission("ekf", false), {p, 6, {}});
    return p;
  }();
  return path;
}

// Records of the stream `suffix` (ODOMETRY, ...) the log used.
std::int64_t used(const MissionLog& log, const std::string& suffix) {
  std::int64_t n = 0;
  for (const auto& [key, count] : log.used)
    if (key.size() > suffix.size() && key.compare(key.size() - suffix.size() - 1, std::string::npos, " " + suffix) == 0)
      n += count;
  return n;
}

// The recorded log, plain, with every "losmimo-rawlog 2" / "format_version = 2" of its CONFIG
// text replaced by version `v`.
std::string with_config_version(int v) {
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::open_file(recorded_log());
  std::string bytes;
  for (int i = 0; std::optional<rawlog_io::RawlogObject> o = reader.next(); ++i) {
    if (i > 0) {
      bytes.append(reinterpret_cast<const char*>(o->bytes.data()), o->bytes.size());
      continue;
    }
    mrpt::obs::CObservationComment c = dynamic_cast<const mrpt::obs::CObservationComment&>(*o->object);
    for (const std::string& key : {std::string(kRawlogMagic) + " ", std::string("format_version = ")}) {
      const std::size_t at = c.text.find(key + std::to_string(kRawlogFormatVersion));
      if (at != std::string::npos) c.text.replace(at + key.size(), 1, std::to_string(v));
    }
    mrpt::io::CMemoryStream mem;
    auto archive = mrpt::serialization::archiveFrom(mem);
    archive << c;
    bytes.append(static_cast<const char*>(mem.getRawBufferData()), static_cast<std::size_t>(mem.getTotalBytesCount()));
  }
  return bytes;
}

TEST(RawlogFormatVersion, ShippedMissions_ReadWholeWithTheStreamsOfTheirVersion) {
  // Version 1 as shipped; scripts/regenerate-golden would re-record them at the current one.
  for (const char* mission : {"nominal", "high_beacon_noise", "beacon_outage"}) {
    const MissionLog log = load_log(source_path(std::string("datasets/missions/") + mission + "/mission.rawlog"));
    EXPECT_TRUE(log.format_version == 1 || log.format_version == kRawlogFormatVersion) << mission;
    EXPECT_TRUE(log.complete) << mission;
    EXPECT_TRUE(log.integrity_error.empty()) << mission << ": " << log.integrity_error;
    EXPECT_TRUE(log.skipped.empty()) << mission;
    EXPECT_EQ(used(log, "ODOMETRY") > 0, log.format_version >= 2) << mission;
    EXPECT_EQ(used(log, "BS_RANGES") > 0, log.format_version >= 2) << mission;
    EXPECT_GT(used(log, "BEACON64"), 0) << mission;
  }
}

// tests/rawlog/data/format_v1: config.ini recorded by losmimo-record at format version 1
// (commit af96c97), and golden/<estimator>/ that version's losmimo-replay --out outputs;
// golden_rerecorded/<estimator>/ the replay outputs of the same config recorded at version 2.
const std::string kV1Sample = "tests/rawlog/data/format_v1";

// summary.csv without the rows today's replay adds to what the goldens' builds wrote (the swarm
// shape split, replay.h); every other row must be as it was.
std::string without_newer_summary_rows(const std::string& csv) {
  std::istringstream in(csv);
  std::string out;
  for (std::string line; std::getline(in, line);) {
    const std::string key = line.substr(0, line.find(','));
    if (key == "common_lateral_m" || key == "shape_lateral_rmse_m" || key == "shape_nees") continue;
    out += line + "\n";
  }
  return out;
}

// The replay's CSV files of `log` with `estimator`, written into `dir`.
void replay_into(const MissionLog& log, const std::string& estimator, const std::string& dir) {
  ReplayOptions options;
  options.estimator = localization::filter_kind_from_string(estimator);
  write_replay_csv(log, replay_mission(log, options), dir);
}

TEST(RawlogFormatVersion, Version1Sample_ReplaysByteForByteAsVersion1Did_AndTodaysRecordingAsItsGolden) {
  const MissionLog v1 = load_log(source_path(kV1Sample + "/mission.rawlog"));
  ASSERT_EQ(v1.format_version, 1);
  ASSERT_TRUE(v1.complete) << v1.stop_description();
  // AND: the same mission recorded today (version 2) replays to its golden_rerecorded outputs.
  const std::string v2_path = temp_path("format_v1_rerecorded.rawlog");
  record_mission(load_mission_config(common::IniConfig::from_file(source_path(kV1Sample + "/config.ini"))),
                 {v2_path, 6, {}});
  const MissionLog v2 = load_log(v2_path);
  ASSERT_EQ(v2.format_version, kRawlogFormatVersion);
  for (const std::string& estimator : {std::string("ekf"), std::string("pf")}) {
    const std::string out1 = temp_path("format_v1_" + estimator), out2 = temp_path("format_v2_" + estimator);
    replay_into(v1, estimator, out1);
    replay_into(v2, estimator, out2);
    for (const char* file : {"estimates.csv", "epochs.csv", "summary.csv"}) {
      const std::string golden = test_support::read_file(source_path(kV1Sample + "/golden/" + estimator + "/" + file));
      ASSERT_FALSE(golden.empty()) << file;
      const bool summary = std::string(file) == "summary.csv";
      const auto as_golden = [summary](const std::string& text) {
        return summary ? without_newer_summary_rows(text) : text;
      };
      EXPECT_EQ(as_golden(test_support::read_file(out1 + "/" + file)), golden)
          << estimator << " " << file << " (version 1)";
      // Recorded by today's build, against golden_rerecorded/: that build's replay of the same
      // mission recorded when the swarm's actuation errors moved to the counter-based stream
      // (swarm.h), which drew other numbers than the v1 recording's mt19937_64. Its planner
      // kernels may round differently from the build that recorded it, and 12 closed-loop
      // epochs carry that into the last digits (measured 7.8e-9, NEES). A recorder that drew or
      // wrote anything differently moves the numbers by the sensors' noise (1e-3 and more), so
      // 1e-7 still tells the two apart.
      const std::string rerecorded =
          test_support::read_file(source_path(kV1Sample + "/golden_rerecorded/" + estimator + "/" + file));
      ASSERT_FALSE(rerecorded.empty()) << file;
      EXPECT_LE(
          test_support::csv_max_relative_difference(as_golden(test_support::read_file(out2 + "/" + file)), rerecorded),
          1e-7)
          << estimator << " " << file << " (version 2)";
    }
  }
}

TEST(RawlogFormatVersion, NewRecording_IsTheCurrentVersionWithTheStandardStreams) {
  const MissionLog log = load_log(recorded_log());
  EXPECT_EQ(log.format_version, kRawlogFormatVersion);
  EXPECT_TRUE(log.complete);
  EXPECT_TRUE(log.skipped.empty());
  EXPECT_EQ(used(log, "ODOMETRY"), 4 * static_cast<std::int64_t>(log.epochs.size()));  // every UAV-epoch
  EXPECT_EQ(used(log, "BS_RANGES"), used(log, "BEACON64"));                            // every beacon
}

TEST(RawlogFormatVersion, UnchangedRewrite_ReadsComplete) {
  // The rewrite alone changes nothing the reader checks (else the next case proves nothing).
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::from_bytes(with_config_version(kRawlogFormatVersion));
  EXPECT_TRUE(load_mission_log(reader).complete);
}

TEST(RawlogFormatVersion, NewerVersion_IsRefusedNamingIt) {
  const int future = kRawlogFormatVersion + 1;
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::from_bytes(with_config_version(future));
  try {
    load_mission_log(reader);
    FAIL() << "a version-" << future << " log was read";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("format version " + std::to_string(future) + " is newer"), std::string::npos)
        << e.what();
  }
  // AND: losmimo-replay says so and exits non-zero.
  const std::string path = temp_path("format_version_future.rawlog");
  test_support::write_file_bytes(path, with_config_version(future));
  std::ostringstream out, err;
  const int code = apps::run_replay_app({path, "", false, false, "", false, true}, out, err);
  EXPECT_NE(code, 0);
  EXPECT_NE(err.str().find("format version " + std::to_string(future)), std::string::npos) << err.str();
}

}  // namespace
}  // namespace losmimo::rawlog
