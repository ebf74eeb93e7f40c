// libFuzzer target: the positions CSV reader and `losmimo-eval`.
//
// Input: a positions CSV. It is parsed by parse_positions_csv and, as a file, evaluated by
// run_eval_app (read_positions_csv + channel + metrics + CSV output), the whole `losmimo-eval` path,
// on a 2 x 2 BS (`--set scenario.bs_rows=2 --set scenario.bs_cols=2`: the same code, and
// ~10x more executions per second than the 16-antenna default).
// Properties (a violation traps, so libFuzzer reports it as a crash):
//   - bad input throws InputError (parse) or returns exit code 2 with a message; any other
//     exception escapes and aborts;
//   - accepted positions are finite, at most max_rows of them;
//   - run_eval_app returns 0 or 2; on 0 it prints every expected line and no "nan".

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "losmimo/apps/lib/eval_app.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/positions_csv.h"

namespace lp = losmimo::placement;

namespace {
constexpr int kMaxRows = 256;

void require(bool ok) {
  if (!ok) __builtin_trap();
}

const std::string& scratch_path() {
  static const std::string path = "/tmp/losmimo-fuzz-positions-" + std::to_string(getpid()) + ".csv";
  return path;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  bool parsed = false;
  try {
    std::istringstream in(text);
    const Eigen::Matrix3Xd q = lp::parse_positions_csv(in, "<fuzz>", kMaxRows);
    require(q.cols() >= 1 && q.cols() <= kMaxRows && q.allFinite());
    parsed = true;
  } catch (const losmimo::common::InputError&) {}

  {
    std::ofstream f(scratch_path(), std::ios::binary | std::ios::trunc);
    f.write(text.data(), static_cast<std::streamsize>(text.size()));
  }
  losmimo::apps::EvalOptions options;
  options.positions_path = scratch_path();
  options.overrides = {"scenario.bs_rows=2", "scenario.bs_cols=2"};
  options.csv = true;
  std::ostringstream out, err;
  const int rc = losmimo::apps::run_eval_app(options, out, err);
  require(rc == 0 || rc == 2);
  if (rc == 2) {
    require(err.str().rfind("losmimo-eval: " + scratch_path(), 0) == 0);
  } else {
    // Parsing is the same with the default 65536-row limit; only more than kMaxRows differs.
    const std::string s = out.str();
    require(s.find("nan") == std::string::npos);
    require(s.find("\nsum_rate_zf_bps_hz,") != std::string::npos);
  }
  require(!parsed || rc == 0 || err.str().find("sits on BS antenna") != std::string::npos);
  return 0;
}
