// Bad rawlogs: truncated at many offsets, random bytes corrupted (seeded), a corrupted
// length field, and a foreign rawlog with types the replay cannot use. Each case: a clear
// report, the readable prefix processed, no crash, no large allocation. No hang: ctest's TIMEOUT
// on these tests (tests/rawlog/CMakeLists.txt) bounds them; they assert no wall-clock time.
#include <gtest/gtest.h>

#include <zlib.h>

#include <cstring>
#include <random>

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRawDAQ.h>
#include <mrpt/serialization/CArchive.h>

#include "losmimo/apps/lib/replay_app.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/fusion/rawlog/mission/recorder.h"
#include "losmimo/fusion/rawlog/mission/replay.h"
#include "rawlog/rawlog_test_util.h"

namespace losmimo::rawlog {
namespace {

using test_support::read_file;
using test_support::small_mission;
using test_support::temp_path;

// One small recorded mission, gzip bytes and uncompressed bytes.
struct Recorded {
  std::string gz, raw;
  std::int64_t objects = 0;
  int epochs = 0;
};

const Recorded& recorded() {
  static const Recorded r = [] {
    Recorded out;
    const std::string path = temp_path("corruption_base.rawlog");
    const RecordResult rec = record_mission(small_mission("ekf", false), {path, 6, {}});
    out.gz = read_file(path);
    out.objects = rec.objects;
    out.epochs = rec.epochs;
    gzFile f = gzopen(path.c_str(), "rb");
    char buf[65536];
    for (int n; (n = gzread(f, buf, sizeof buf)) > 0;) out.raw.append(buf, static_cast<std::size_t>(n));
    gzclose(f);
    return out;
  }();
  return r;
}

// Strict reader (nothing MRPT parses unchecked) + the interpreter, on bytes.
MissionLog load_bytes(const std::string& bytes) {
  rawlog_io::RawlogReaderOptions strict;
  strict.foreign = rawlog_io::ForeignObjects::kStop;
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::from_bytes(bytes, strict);
  return load_mission_log(reader);
}

TEST(RawlogCorruption, TruncatedAtManyOffsets_PrefixProcessedAndReported) {
  const Recorded& r = recorded();
  ASSERT_GT(r.gz.size(), 1000u);
  for (const bool compressed : {true, false}) {
    const std::string& full = compressed ? r.gz : r.raw;
    for (const double fraction : {0.05, 0.2, 0.37, 0.5, 0.73, 0.9, 0.999}) {
      // GIVEN: the file cut at this fraction of its bytes.
      const std::size_t cut = static_cast<std::size_t>(fraction * static_cast<double>(full.size()));
      const std::string bytes = full.substr(0, cut);
      // WHEN
      rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::from_bytes(bytes);
      std::int64_t n = 0;
      while (reader.next()) ++n;
      // THEN: stopped as truncated, saying where; fewer objects than written.
      const rawlog_io::RawlogReadStatus& s = reader.status();
      SCOPED_TRACE((compressed ? "gzip cut at " : "plain cut at ") + std::to_string(cut));
      EXPECT_EQ(s.stop, rawlog_io::RawlogStop::kTruncated) << s.describe();
      EXPECT_LT(n, r.objects);
      EXPECT_EQ(s.objects, n);
      EXPECT_NE(s.describe().find("object " + std::to_string(n)), std::string::npos) << s.describe();
      // AND: the verified epochs before the cut are replayed (late cuts keep most of them).
      if (n > 0) {
        const MissionLog log = load_bytes(bytes);
        EXPECT_FALSE(log.complete);
        EXPECT_LE(static_cast<int>(log.epochs.size()), r.epochs);
        if (fraction >= 0.5) {
          EXPECT_GE(static_cast<int>(log.epochs.size()), r.epochs / 3);
          EXPECT_NO_THROW(replay_mission(log, {}));
        }
      }
    }
  }
}

// The uncompressed offsets of the EPOCH_END marks, in order (mark k closes epoch k), and the
// size of each.
std::vector<std::pair<std::size_t, std::size_t>> epoch_marks(const std::string& raw) {
  std::vector<std::pair<std::size_t, std::size_t>> marks;
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::from_bytes(raw);
  const std::string head = std::string("losmimo ") + kLabelEpochEnd + "\n";
  while (const std::optional<rawlog_io::RawlogObject> o = reader.next()) {
    const auto* c = dynamic_cast<const mrpt::obs::CObservationComment*>(o->object.get());
    if (c && c->text.compare(0, head.size(), head) == 0) marks.emplace_back(o->offset, o->bytes.size());
  }
  return marks;
}

TEST(RawlogCorruption, TruncatedInsideEveryEpoch_KeepsExactlyTheEpochsBefore_ReplayedBitForBit) {
  const Recorded& r = recorded();
  const std::vector<std::pair<std::size_t, std::size_t>> marks = epoch_marks(r.raw);
  ASSERT_EQ(static_cast<int>(marks.size()), r.epochs);
  for (int k = 0; k < r.epochs; ++k) {
    const auto [mark, size] = marks[static_cast<std::size_t>(k)];
    // GIVEN: the log cut inside epoch k: inside its last record before the mark, at the mark's
    // first byte (an object boundary), and inside the mark.
    for (const std::size_t cut : {mark - 1, mark, mark + size / 2}) {
      SCOPED_TRACE("epoch " + std::to_string(k) + ", cut at " + std::to_string(cut));
      const MissionLog log = load_bytes(r.raw.substr(0, cut));
      // THEN: exactly the k verified epochs before it, never a partial one.
      EXPECT_FALSE(log.complete);
      ASSERT_EQ(static_cast<int>(log.epochs.size()), k);
      if (k == 0) continue;
      // AND: their replay reproduces every logged belief bit for bit.
      const ReplayResult replay = replay_mission(log, {});
      EXPECT_EQ(replay.filter_beliefs_compared, k * log.num_uavs);
      EXPECT_EQ(replay.filter_beliefs_bitwise_equal, replay.filter_beliefs_compared);
    }
  }
}

TEST(RawlogCorruption, RandomBytesCorrupted_StopsCleanlyWithAReason) {
  constexpr int kCases = 200;
  const Recorded& r = recorded();
  std::mt19937_64 rng(20261123);
  int stopped_early = 0, integrity_caught = 0;
  for (int i = 0; i < kCases; ++i) {
    // GIVEN: 1 to 8 random bytes overwritten, in the gzip file (even cases) or in the plain one.
    std::string bytes = (i % 2 == 0) ? r.gz : r.raw;
    const int flips = 1 + static_cast<int>(rng() % 8);
    for (int f = 0; f < flips; ++f) {
      const std::size_t at = 10 + rng() % (bytes.size() - 10);
      bytes[at] = static_cast<char>(rng() & 0xFF);
    }
    // WHEN: strict read + interpretation.
    MissionLog log;
    try {
      log = load_bytes(bytes);
    } catch (const common::InputError&) {
      continue;  // the CONFIG itself (object 0) was hit: bad input, reported as such
    }
    // THEN: either stopped with a reason, or an integrity mark caught it, or (a change inside
    // a value that no check covers: the digest catches those) it is complete.
    if (log.read_status.stop != rawlog_io::RawlogStop::kEnd) {
      ++stopped_early;
      EXPECT_FALSE(log.read_status.reason.empty());
    }
    if (!log.integrity_error.empty()) ++integrity_caught;
    EXPECT_TRUE(log.read_status.stop != rawlog_io::RawlogStop::kEnd || !log.integrity_error.empty() || !log.complete ||
                bytes == r.gz || bytes == r.raw)
        << "case " << i << ": corruption not detected";
  }
  EXPECT_GT(stopped_early + integrity_caught, kCases / 2);
}

TEST(RawlogCorruption, HugeVectorLength_RefusedWithoutAllocating) {
  // GIVEN: a plain rawlog whose first RawDAQ's AIN_8bits length says 0xFFFFFFF0.
  const Recorded& r = recorded();
  std::string bytes = r.raw;
  const std::string name = "mrpt::obs::CObservationRawDAQ";
  const std::size_t at = bytes.find(name);
  ASSERT_NE(at, std::string::npos);
  // header (1 + name + version), label (4 + n), timestamp 8, sample_rate 8, then AIN_8bits length.
  std::uint32_t label_len = 0;
  std::memcpy(&label_len, bytes.data() + at + name.size() + 1, 4);
  const std::size_t length_at = at + name.size() + 1 + 4 + label_len + 16;
  const std::uint32_t huge = 0xFFFFFFF0u;
  std::memcpy(bytes.data() + length_at, &huge, 4);
  // WHEN: read with the default (non-strict) options.
  const rawlog_io::RawlogContents c = rawlog_io::read_rawlog_bytes(bytes);
  // THEN: refused by the length check, the objects before it returned.
  EXPECT_EQ(c.status.stop, rawlog_io::RawlogStop::kLimit) << c.status.describe();
  EXPECT_NE(c.status.reason.find("AIN_8bits"), std::string::npos) << c.status.reason;
  EXPECT_GT(c.objects.size(), 0u);
}

TEST(RawlogForeign, BearingRangeAndOdometry_AreUsedAndTheRestListedAndSkipped) {
  // GIVEN: a rawlog written with MRPT's own gzip stream by "another tool": one UAV, beacon
  // bearing-range + cumulative 2-D odometry, plus an IMU and a RawDAQ it cannot use.
  const std::string path = temp_path("foreign.rawlog");
  constexpr int kEpochs = 20;
  {
    mrpt::io::CFileGZOutputStream f(path);
    auto a = mrpt::serialization::archiveFrom(f);
    for (int k = 0; k < kEpochs; ++k) {
      const Eigen::Vector3d q(1000.0 + 0.1 * k, 0.05 * k, 0.0);
      mrpt::obs::CObservationOdometry odo;
      odo.sensorLabel = "ODOMETRY";
      odo.odometry = mrpt::poses::CPose2D(0.1 * k, 0.05 * k, 0.0);
      a << odo;
      mrpt::obs::CObservationBearingRange b;
      b.sensorLabel = "BEACON";
      mrpt::obs::CObservationBearingRange::TMeasurement z;
      z.range = static_cast<float>(q.norm());
      z.yaw = static_cast<float>(std::atan2(q.y(), q.x()));
      z.pitch = 0.0f;
      z.landmarkID = 0;
      b.sensedData.push_back(z);
      a << b;
      mrpt::obs::CObservationIMU imu;
      imu.sensorLabel = "IMU";
      a << imu;
    }
    mrpt::obs::CObservationRawDAQ daq;
    daq.sensorLabel = "ADC";
    a << daq;
  }
  // WHEN
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::open_file(path);
  const MissionLog log = load_mission_log(reader);
  // THEN: foreign, complete, one UAV with an epoch per odometry reading, skips listed.
  EXPECT_FALSE(log.ours);
  EXPECT_EQ(log.read_status.stop, rawlog_io::RawlogStop::kEnd) << log.read_status.describe();
  EXPECT_EQ(log.num_uavs, 1);
  ASSERT_EQ(static_cast<int>(log.epochs.size()), kEpochs);
  EXPECT_EQ(log.skipped.at("mrpt::obs::CObservationIMU IMU"), kEpochs);
  EXPECT_EQ(log.skipped.at("mrpt::obs::CObservationRawDAQ ADC"), 1);
  EXPECT_EQ(log.used.at("mrpt::obs::CObservationBearingRange BEACON"), kEpochs);
  ASSERT_TRUE(log.epochs[3][0].displacement_m.has_value());
  EXPECT_NEAR(log.epochs[3][0].displacement_m->x(), 0.1, 1e-12);
  EXPECT_NEAR(log.epochs[3][0].displacement_m->y(), 0.05, 1e-12);
  ASSERT_TRUE(log.epochs[3][0].beacon.has_value());
  // AND: the replay runs and lists the skipped types.
  const ReplayResult r = replay_mission(log, {});
  EXPECT_EQ(r.num_beacons, kEpochs);
  EXPECT_EQ(r.num_inexact_beacons, kEpochs);
  std::ostringstream out, err;
  EXPECT_EQ(apps::run_replay_app({path, "ekf", false, false, "", false}, out, err), 0) << err.str();
  EXPECT_NE(out.str().find("skipped mrpt::obs::CObservationIMU IMU = 20"), std::string::npos) << out.str();
  // AND: strict mode stops at the first class it cannot bound (the odometry and bearing-range
  // are bounded: object 2, the IMU), and says which.
  std::ostringstream out2, err2;
  EXPECT_EQ(apps::run_replay_app({path, "ekf", false, false, "", true}, out2, err2), 1)
      << err2.str();  // a stopped read
  EXPECT_NE(err2.str().find("stopped at object 2 (uncompressed byte 327): limit: mrpt::obs::CObservationIMU"),
            std::string::npos)
      << err2.str();
}

}  // namespace
}  // namespace losmimo::rawlog

namespace losmimo::rawlog {
namespace {

TEST(RawlogCorruption, BadConfigInAnOwnLog_IsBadInputNamingTheKey) {
  // GIVEN: a log that claims to be ours, with a CONFIG whose [rawlog] filter_seeds is junk.
  const std::string path = test_support::temp_path("bad_config.rawlog");
  {
    mrpt::io::CFileGZOutputStream f(path);
    auto a = mrpt::serialization::archiveFrom(f);
    mrpt::obs::CObservationComment c;
    c.text = "losmimo-rawlog 1\n[scenario]\nnum_uavs = 2\n\n[rawlog]\nnum_uavs = 2\nfilter_seeds = 1, x\n";
    a << c;
  }
  // WHEN / THEN
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::open_file(path);
  EXPECT_THROW(load_mission_log(reader), common::InputError);
  std::ostringstream out, err;
  EXPECT_EQ(apps::run_replay_app({path, "", false, false, "", false}, out, err), 2);
  EXPECT_NE(err.str().find("filter_seeds"), std::string::npos) << err.str();
}

}  // namespace
}  // namespace losmimo::rawlog
