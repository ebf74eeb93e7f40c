// losmimo-replay's outputs say "complete" exactly when the exit code does; a log with nothing
// to replay still says why reading stopped; empty or stray options of losmimo-replay and
// losmimo-record are refused.
#include <gtest/gtest.h>

#include <unistd.h>
#include <zlib.h>

#include <filesystem>

#include "losmimo/apps/lib/record_app.h"
#include "losmimo/apps/lib/replay_app.h"
#include "losmimo/fusion/rawlog/mission/recorder.h"
#include "rawlog/rawlog_test_util.h"

namespace losmimo::rawlog {
namespace {

namespace fs = std::filesystem;
using test_support::read_file;
using test_support::temp_path;
using test_support::write_file_bytes;

struct Logs {
  std::string gz, plain;
};
const Logs& logs() {
  static const Logs l = [] {
    Logs out;
    const std::string path = temp_path("complete_base.rawlog");
    record_mission(test_support::small_mission("ekf", false), {path, 6, {}});
    out.gz = read_file(path);
    gzFile f = gzopen(path.c_str(), "rb");
    char buf[65536];
    for (int n; (n = gzread(f, buf, sizeof buf)) > 0;) out.plain.append(buf, static_cast<std::size_t>(n));
    gzclose(f);
    return out;
  }();
  return l;
}

struct Replay {
  int code;
  std::string err, summary, manifest;
};
Replay replay(const std::string& bytes, const std::string& name) {
  const std::string path = temp_path(name + ".rawlog"), out_dir = temp_path(name + "_out");
  write_file_bytes(path, bytes);
  fs::remove_all(out_dir);
  std::ostringstream out, err;
  Replay r;
  r.code = apps::run_replay_app({path, "", false, false, out_dir, false}, out, err);
  r.err = err.str();
  r.summary = read_file(out_dir + "/summary.csv");
  r.manifest = read_file(out_dir + "/losmimo-run.ini");
  return r;
}

TEST(ReplayComplete, IntactLog_Exits0AndSaysComplete) {
  const Replay r = replay(logs().gz, "complete_ok");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.summary.find("\ncomplete,true\n"), std::string::npos) << r.summary;
  EXPECT_NE(r.manifest.find("complete = true\nexit_code = 0\n"), std::string::npos) << r.manifest;
}

// The exit code and summary.csv agree: a log missing its gzip trailer or with bytes after its
// end is incomplete in both.
TEST(ReplayComplete, MissingGzipTrailerOrJunkAfterTheEnd_Exits1AndSaysIncomplete) {
  const std::string gz = logs().gz;
  for (const auto& [name, bytes] : {std::make_pair(std::string("complete_trailer"), gz.substr(0, gz.size() - 8)),
                                    std::make_pair(std::string("complete_junk"), logs().plain + "JUNKJUNK")}) {
    SCOPED_TRACE(name);
    const Replay r = replay(bytes, name);
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_NE(r.summary.find("\ncomplete,false\n"), std::string::npos) << r.summary;
    EXPECT_NE(r.manifest.find("complete = false\nexit_code = 1\n"), std::string::npos) << r.manifest;
  }
}

// Used to say only "rawlog holds no epoch of any UAV: nothing to replay".
TEST(ReplayComplete, CorruptionInsideEpoch0_Exits2WithTheReasonReadingStopped) {
  std::string plain = logs().plain;
  const std::size_t at = plain.find("UAV00_TRUTH");
  ASSERT_NE(at, std::string::npos);
  plain[at + 10] = 'X';
  const Replay r = replay(plain, "complete_epoch0");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("nothing to replay"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("integrity: EPOCH_END mark at object"), std::string::npos) << r.err;
}

TEST(ReplayComplete, EmptyOut_IsRefused) {
  const std::string path = temp_path("complete_empty_out.rawlog");
  write_file_bytes(path, logs().gz);
  std::ostringstream out, err;
  apps::ReplayAppOptions o{path, "", false, false, "", false};
  o.out_given = true;
  EXPECT_EQ(apps::run_replay_app(o, out, err), 2);
  EXPECT_NE(err.str().find("--out ''"), std::string::npos) << err.str();
}

// losmimo-record checks the [experiment] values of an experiment config too.
TEST(RecordApp, BadExperimentKey_Exits2NamingIt) {
  std::ostringstream out, err;
  apps::RecordAppOptions o;
  o.overrides = {"experiment.algorithms=not_an_algorithm"};
  o.out_path = temp_path("record_bad_experiment.rawlog");
  EXPECT_EQ(apps::run_record_app(o, out, err), 2);
  EXPECT_NE(err.str().find("not_an_algorithm"), std::string::npos) << err.str();
  EXPECT_FALSE(fs::exists(o.out_path + ".partial"));
}

}  // namespace
}  // namespace losmimo::rawlog
