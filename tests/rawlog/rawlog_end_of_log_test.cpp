// END_OF_LOG's run status and fault (log.h): a log of a run ended by a fault, its
// END_OF_LOG rewritten (a consistent text_digest, so only the reader's field checks can object):
// a log written before the reason was logged, bad fields named with their values, and a reason
// with commas quoted in summary.csv.
#include <gtest/gtest.h>

#include <functional>
#include <optional>
#include <stdexcept>
#include <sstream>
#include <string>
#include <vector>

#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/serialization/CArchive.h>

#include "fusion/closed_loop_fixtures.h"
#include "losmimo/apps/lib/replay_app.h"
#include "losmimo/fusion/rawlog/mission/format.h"
#include "losmimo/fusion/rawlog/mission/recorder.h"
#include "losmimo/fusion/rawlog/mission/replay.h"
#include "rawlog/rawlog_test_util.h"

namespace losmimo::rawlog {
namespace {

using test_support::contains;
using test_support::read_file;
using test_support::small_mission;
using test_support::temp_path;
using test_support::write_file_bytes;

constexpr const char* kReason =
    "UAV 2: no measurement and no motion for 3 iterations (since iteration 4) at iteration 6";

// The recorded log of the small mission whose UAV 2 dies at iteration 4 (found at iteration 6);
// one per process (ctest runs the tests of this file in parallel processes).
const std::string& dead_uav_log() {
  static const std::string path = [] {
    const std::string p = temp_path("end_of_log_base.rawlog");
    record_mission(small_mission("ekf", false, "faults = unresponsive:2:4\n"), {p, 6, {}});
    return p;
  }();
  return path;
}

// The "key = ..." line of a mark's text replaced by `line` (removed if `line` is empty).
std::string replace_line(std::string text, const std::string& key, const std::string& line) {
  const std::size_t at = text.find("\n" + key + " = ");
  if (at == std::string::npos) return text;
  const std::size_t end = text.find('\n', at + 1);
  return line.empty() ? text.erase(at, end - at) : text.replace(at + 1, end - at - 1, line);
}

// The log, plain (uncompressed), with END_OF_LOG's text (without its text_digest line) edited.
std::string with_end_of_log(const std::function<std::string(const std::string&)>& edit) {
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::open_file(dead_uav_log());
  std::vector<rawlog_io::RawlogObject> objects;
  while (std::optional<rawlog_io::RawlogObject> o = reader.next()) objects.push_back(std::move(*o));
  std::string bytes;
  for (std::size_t i = 0; i + 1 < objects.size(); ++i)
    bytes.append(reinterpret_cast<const char*>(objects[i].bytes.data()), objects[i].bytes.size());
  const auto* end =
      objects.empty() ? nullptr : dynamic_cast<const mrpt::obs::CObservationComment*>(objects.back().object.get());
  if (!end) throw std::runtime_error(dead_uav_log() + ": does not end with END_OF_LOG");
  mrpt::obs::CObservationComment mark = *end;
  mark.text = with_text_digest(edit(mark.text.substr(0, mark.text.rfind("text_digest = "))));
  mrpt::io::CMemoryStream mem;
  auto archive = mrpt::serialization::archiveFrom(mem);
  archive << mark;
  bytes.append(static_cast<const char*>(mem.getRawBufferData()), static_cast<std::size_t>(mem.getTotalBytesCount()));
  return bytes;
}

MissionLog load_bytes(const std::string& bytes) {
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::from_bytes(bytes);
  return load_mission_log(reader);
}

struct AppRun {
  int code = -1;
  std::string out, err, summary_csv;
};
AppRun replay_app(const std::string& bytes, const std::string& name) {
  const std::string path = temp_path(name + ".rawlog");
  write_file_bytes(path, bytes);
  std::ostringstream out, err;
  AppRun a;
  a.code = apps::run_replay_app({path, "", false, false, temp_path(name + "_out"), false, true}, out, err);
  a.out = out.str();
  a.err = err.str();
  a.summary_csv = read_file(temp_path(name + "_out") + "/summary.csv");
  return a;
}

TEST(RawlogEndOfLog, UnchangedRewrite_ReadsAsTheRecordedLog) {
  // The rewrite alone changes nothing the reader checks (else the cases below prove nothing).
  const MissionLog log = load_bytes(with_end_of_log([](const std::string& t) { return t; }));
  EXPECT_TRUE(log.complete) << log.stop_description();
  EXPECT_EQ(log.run_end.status, "uav_unresponsive");
  EXPECT_EQ(log.run_end.fault_uav, 2);
  EXPECT_EQ(log.run_end.fault, kReason);
}

TEST(RawlogEndOfLog, FaultedLogWithoutTheReason_StillReportsTheFaultAndExits3) {
  // GIVEN: a faulted run's END_OF_LOG as written before fault_uav and fault were logged.
  const std::string bytes =
      with_end_of_log([](const std::string& t) { return replace_line(replace_line(t, "fault_uav", ""), "fault", ""); });
  // WHEN
  const MissionLog log = load_bytes(bytes);
  const AppRun app = replay_app(bytes, "end_of_log_no_reason");
  // THEN
  EXPECT_TRUE(log.complete) << log.stop_description();
  EXPECT_TRUE(log.run_faulted());
  EXPECT_EQ(log.run_end.fault_uav, -1);
  EXPECT_EQ(log.run_end.fault, "");
  EXPECT_EQ(app.code, 3) << app.err;
  EXPECT_TRUE(contains(app.err, "ended by a fault (uav_unresponsive): reason not in the log")) << app.err;
  EXPECT_TRUE(contains(app.summary_csv, "\nfault,(not in the log)\n")) << app.summary_csv;
}

TEST(RawlogEndOfLog, BadStatusOrFaultFields_TheLogIsIncompleteNamingFieldAndValue) {
  struct Case {
    std::string key, line, expected;
  };
  const std::vector<Case> cases = {
      {"status", "status = exploded", "status = 'exploded': not a run status"},
      {"status", "", "status = '': not a run status"},
      {"fault_uav", "fault_uav = 9", "fault_uav = '9': not a UAV index in [-1, 3]"},
      {"fault_uav", "fault_uav = 2x", "fault_uav = '2x'"},
      {"status", "status = converged", "fault = '" + std::string(kReason) + "' with status = converged"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.line);
    // GIVEN
    const std::string bytes = with_end_of_log([&](const std::string& t) {
      if (c.line == "status = converged") return replace_line(replace_line(t, "fault_uav", ""), c.key, c.line);
      return replace_line(t, c.key, c.line);
    });
    // WHEN
    const MissionLog log = load_bytes(bytes);
    const AppRun app = replay_app(bytes, "end_of_log_bad");
    // THEN: the epochs are there, END_OF_LOG is refused with the field and value, exit 1.
    EXPECT_FALSE(log.complete);
    EXPECT_EQ(log.epochs.size(), 6u);
    EXPECT_TRUE(contains(log.integrity_error, "END_OF_LOG mark at object")) << log.integrity_error;
    EXPECT_TRUE(contains(log.integrity_error, c.expected)) << log.integrity_error;
    EXPECT_EQ(app.code, 1) << app.err;
    EXPECT_TRUE(contains(app.err, c.expected)) << app.err;
  }
}

TEST(RawlogEndOfLog, ReasonWithCommas_IsOneQuotedFieldOfSummaryCsv) {
  // GIVEN: a numerical fault's reason, which holds commas (placement::check_finite's wording).
  const std::string reason = "UAV 3: commanded move is non-finite (r = (nan, 0, 0)) at iteration 4";
  const std::string bytes = with_end_of_log([&](const std::string& t) {
    return replace_line(
        replace_line(replace_line(t, "status", "status = numerical_fault"), "fault_uav", "fault_uav = 3"), "fault",
        "fault = " + reason);
  });
  // WHEN
  const AppRun app = replay_app(bytes, "end_of_log_commas");
  // THEN
  EXPECT_EQ(app.code, 3) << app.err;
  EXPECT_TRUE(contains(app.summary_csv, "\nfault,\"" + reason + "\"\n")) << app.summary_csv;
  EXPECT_TRUE(contains(app.out, "\nfault = " + reason + "\n")) << app.out;
}

}  // namespace
}  // namespace losmimo::rawlog
