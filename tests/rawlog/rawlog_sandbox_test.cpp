// Foreign rawlogs cannot crash the replay: objects of logs losmimo did not write are parsed in a
// bounded child process (rawlog_io/sandbox.h). A crash of MRPT's deserializer, its memory limit or
// its CPU limit there stops the read with a status naming the object index, byte offset and
// class; the objects before it are kept. losmimo's own logs stay in this process.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include "losmimo/apps/lib/replay_app.h"
#include "losmimo/placement/common/test_hook.h"
#include "losmimo/fusion/rawlog/mission/log.h"
#include "losmimo/fusion/rawlog/io/reader.h"
#include "rawlog/rawlog_test_util.h"

namespace losmimo::rawlog_io {
namespace {

using test_support::read_file;
using test_support::temp_path;
using test_support::write_file_bytes;

constexpr int kActions = 6;
constexpr int kCrashAt = 3;  // the action whose estimationMethod is corrupted

// A foreign log (MRPT's sensory-frame format, plain): kActions odometry actions, each followed by
// an empty sensory frame: objects 0, 2, 4, ... are actions.
std::string odometry_log() {
  const std::string path = temp_path("sandbox_odometry.rawlog");
  {
    mrpt::io::CFileOutputStream f(path);
    auto a = mrpt::serialization::archiveFrom(f);
    for (int k = 0; k < kActions; ++k) {
      mrpt::obs::CActionRobotMovement2D m;
      m.computeFromOdometry(mrpt::poses::CPose2D(0.1, 0.0, 0.01),
                            mrpt::obs::CActionRobotMovement2D::TMotionModelOptions());
      mrpt::obs::CActionCollection acts;
      acts.insert(m);
      mrpt::obs::CSensoryFrame sf;
      a << acts << sf;
    }
  }
  return read_file(path);
}

// The offset of the n-th occurrence of `what`.
std::size_t nth(const std::string& bytes, const std::string& what, int n) {
  std::size_t at = 0;
  for (int i = 0; i <= n; ++i) at = bytes.find(what, i == 0 ? 0 : at + 1);
  return at;
}

// The same log with action kCrashAt's estimationMethod set to 1: MRPT then reads a CPosePDF where
// a CPose2D is, gets null and dereferences it (SIGSEGV in CActionRobotMovement2D::serializeFrom).
std::string crashing_log(std::size_t* crash_offset) {
  std::string bytes = odometry_log();
  const std::string name = "CActionRobotMovement2D";
  const std::size_t at = nth(bytes, name, kCrashAt);
  EXPECT_NE(at, std::string::npos);
  const std::int32_t method = 1;
  std::memcpy(bytes.data() + at + name.size() + 1, &method, 4);  // after the version byte
  // The CActionCollection that holds it starts at its 1-byte name length before "mrpt::obs::".
  *crash_offset = nth(bytes, "CActionCollection", kCrashAt) - 1 - std::string("mrpt::obs::").size();
  return bytes;
}

TEST(RawlogSandbox, ForeignLog_IsReadCompletelyThroughTheSandbox) {
  const RawlogContents c = read_rawlog_bytes(odometry_log());
  EXPECT_EQ(c.status.stop, RawlogStop::kEnd) << c.status.describe();
  EXPECT_EQ(static_cast<int>(c.objects.size()), 2 * kActions);
  EXPECT_NE(dynamic_cast<const mrpt::obs::CActionCollection*>(c.objects[2].object.get()), nullptr);
}

TEST(RawlogSandbox, CrashInMrptsDeserializer_StopsNamingObjectOffsetAndClass) {
  // GIVEN: the crashing log; read in this process, MRPT would take the process down (a death
  // test, so that this process survives to check it).
  std::size_t offset = 0;
  const std::string bytes = crashing_log(&offset);
  RawlogReaderOptions in_process;
  in_process.foreign = ForeignObjects::kInProcess;
  EXPECT_DEATH(read_rawlog_bytes(bytes, in_process), "");
  // WHEN: read as the replay reads it.
  const RawlogContents c = read_rawlog_bytes(bytes);
  // THEN: the objects before it, and a corrupt stop at object 2 * kCrashAt, its offset and class.
  EXPECT_EQ(c.status.stop, RawlogStop::kCorrupt);
  EXPECT_EQ(c.status.objects, 2 * kCrashAt);
  EXPECT_EQ(static_cast<int>(c.objects.size()), 2 * kCrashAt);
  EXPECT_EQ(c.status.offset, offset);
  const std::string d = c.status.describe();
  EXPECT_NE(
      d.find("stopped at object " + std::to_string(2 * kCrashAt) + " (uncompressed byte " + std::to_string(offset) +
             "): corrupt: mrpt::obs::CActionCollection: MRPT's parser crashed in the sandbox (SEGV"),
      std::string::npos)
      << d;
  // AND: the sandbox serves the next log (a new child).
  EXPECT_EQ(read_rawlog_bytes(odometry_log()).status.stop, RawlogStop::kEnd);
}

TEST(RawlogSandbox, AllocationAboveTheMemoryLimit_StopsWithACleanError) {
  // GIVEN: a sensory frame whose observation count says 2^24: MRPT sizes a vector of 2^24
  // pointers (256 MiB) before reading them.
  const std::string path = temp_path("sandbox_frame.rawlog");
  {
    mrpt::io::CFileOutputStream f(path);
    auto a = mrpt::serialization::archiveFrom(f);
    mrpt::obs::CObservationOdometry odo;
    a << odo;
    mrpt::obs::CSensoryFrame sf;
    sf.insert(mrpt::obs::CObservationOdometry::Create());
    a << sf;
  }
  std::string bytes = read_file(path);
  const std::size_t at = bytes.find("CSensoryFrame") + std::strlen("CSensoryFrame") + 1;
  const std::uint32_t count = 1u << 24;
  std::memcpy(bytes.data() + at, &count, 4);
  RawlogReaderOptions o;
  o.sandbox.memory_bytes = std::size_t{64} << 20;
  // WHEN
  const RawlogContents c = read_rawlog_bytes(bytes, o);
  // THEN: object 0 read; object 1 stopped, named, without this process allocating anything.
  EXPECT_EQ(c.objects.size(), 1u);
  EXPECT_NE(c.status.stop, RawlogStop::kEnd);
  EXPECT_EQ(c.status.objects, 1);
  EXPECT_NE(c.status.describe().find("stopped at object 1 (uncompressed byte "), std::string::npos)
      << c.status.describe();
  EXPECT_NE(c.status.reason.find("CSensoryFrame"), std::string::npos) << c.status.reason;
}

TEST(RawlogSandbox, ParserThatSpinsOrHangs_IsStoppedByTheCpuLimitOrTheWatchdog) {
  // The sandbox child spins or hangs at the pause point "sandbox.parsing" (common/test_hook.h).
  ASSERT_TRUE(common::test_hooks_compiled_in())
      << "needs the test hooks: configure with -DLOSMIMO_TEST_HOOKS=ON (the default with the tests)";
  const std::string bytes = odometry_log();
  struct Case {
    const char* pause;
    int cpu_seconds, stall_seconds;
    const char* expected;
  };
  for (const Case& k : {Case{"sandbox.parsing#3:spin", 1, 60, "s of CPU in the sandbox"},
                        Case{"sandbox.parsing#3", 61, 1, "no result for 1 s"}}) {
    SCOPED_TRACE(k.pause);
    ::setenv("LOSMIMO_TEST_PAUSE", k.pause, 1);
    RawlogReaderOptions o;  // limits of its own: a fresh child, which sees the variable
    o.sandbox.cpu_seconds = k.cpu_seconds;
    o.sandbox.stall_seconds = k.stall_seconds;
    const RawlogContents c = read_rawlog_bytes(bytes, o);
    ::unsetenv("LOSMIMO_TEST_PAUSE");
    EXPECT_EQ(c.status.stop, RawlogStop::kLimit) << c.status.describe();
    EXPECT_EQ(c.status.objects, 2);  // the sandbox parses from object 0: its 3rd is object 2
    EXPECT_NE(c.status.reason.find(k.expected), std::string::npos) << c.status.reason;
  }
}

TEST(RawlogSandbox, OwnLogWithAClassLosmimoNeverWrites_StopsInProcessWithoutTheSandbox) {
  const std::string path = temp_path("sandbox_own.rawlog");
  {
    mrpt::io::CFileOutputStream f(path);
    auto a = mrpt::serialization::archiveFrom(f);
    mrpt::obs::CObservationComment c;
    c.text = "losmimo-rawlog 1\n[scenario]\nnum_uavs = 4\n";
    a << c;
    mrpt::obs::CObservationIMU imu;
    a << imu;
  }
  const RawlogContents c = read_rawlog_bytes(read_file(path));
  EXPECT_EQ(c.objects.size(), 1u);
  EXPECT_EQ(c.status.stop, RawlogStop::kLimit);
  EXPECT_NE(c.status.reason.find("CObservationIMU in a losmimo rawlog, which never holds one"), std::string::npos)
      << c.status.reason;
}

TEST(RawlogSandbox, ReplayOfTheCrashingLog_Exits1NamingTheObject) {
  std::size_t offset = 0;
  const std::string path = temp_path("sandbox_crash.rawlog");
  write_file_bytes(path, crashing_log(&offset));
  std::ostringstream out, err;
  EXPECT_EQ(apps::run_replay_app({path, "", false, false, "", false}, out, err), 1) << err.str();
  EXPECT_NE(err.str().find("stopped at object " + std::to_string(2 * kCrashAt) + " (uncompressed byte " +
                           std::to_string(offset) + ")"),
            std::string::npos)
      << err.str();
  // Each action before the crash opens an epoch after the first.
  EXPECT_NE(out.str().find("epochs = " + std::to_string(kCrashAt + 1) + "\n"), std::string::npos) << out.str();
}

}  // namespace
}  // namespace losmimo::rawlog_io
