#include "losmimo/experiment/records.h"

#include <algorithm>
#include <cstdlib>
#include <istream>
#include <ostream>
#include <sstream>

#include "losmimo/common/format.h"
#include "losmimo/common/input_error.h"
#include "losmimo/experiment/metrics.h"

namespace losmimo::experiment {

using common::InputError;
using common::parse_integer;

namespace {
// Full precision (round trip): the checkpoint and shard records.
std::string exact(double v) { return common::format_g(v, common::kExactDigits); }

void write_matrix(std::ostream& out, const Eigen::Matrix3Xd& q) {
  out << "," << q.cols();
  for (Eigen::Index n = 0; n < q.cols(); ++n) {
    for (int i = 0; i < 3; ++i) out << "," << exact(q(i, n));
  }
}

}  // namespace

void write_record_lines(std::ostream& out, int point, const std::vector<TrialRecord>& records) {
  for (const TrialRecord& r : records) {
    out << "r," << point << "," << r.sweep << "," << exact(r.value) << "," << r.algorithm << "," << r.trial << ","
        << r.seed << "," << r.start_seed << "," << r.status;
    for (const Metric& m : kMetrics) out << "," << exact(m.get(r));
    out << "," << r.extra.size();
    for (const double v : r.extra) out << "," << exact(v);
    write_matrix(out, r.start_m);
    write_matrix(out, r.final_m);
    out << "\n";
  }
}

void write_point_done(std::ostream& out, int point) { out << "d," << point << "\n"; }

RecordLines parse_record_lines(std::istream& in, const std::string& origin, bool allow_truncated_tail) {
  std::ostringstream buffer;
  buffer << in.rdbuf();
  std::string text = buffer.str();
  if (!text.empty() && text.back() != '\n') {
    if (!allow_truncated_tail) throw common::InputError(origin + ": truncated last line");
    text.erase(text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1);
  }
  RecordLines result;
  std::istringstream lines(text);
  std::string line;
  int line_no = 0;
  while (std::getline(lines, line)) {
    ++line_no;
    if (line.rfind(kRecordsMagic, 0) == 0 && line != kRecordsHeader) {
      throw common::InputError(origin + ":" + std::to_string(line_no) + ": '" + line + "': written by another losmimo version (expected '" +
                               kRecordsHeader + "'); run that experiment again");
    }
    if (line.empty() || line[0] == '#') continue;
    const std::string where = origin + ":" + std::to_string(line_no);
    std::vector<std::string> f;
    {
      std::istringstream ls(line);
      std::string field;
      while (std::getline(ls, field, ',')) f.push_back(field);
    }
    std::size_t k = 0;
    const auto next = [&]() -> const std::string& {
      if (k >= f.size()) throw common::InputError(where + ": too few fields");
      return f[k++];
    };
    const auto integer = [&](long long lo, long long hi) { return common::parse_integer(next(), where, lo, hi); };
    const auto real = [&]() {
      const std::string& t = next();
      char* end = nullptr;
      const double v = std::strtod(t.c_str(), &end);
      if (t.empty() || end != t.c_str() + t.size()) throw common::InputError(where + ": '" + t + "' is not a number");
      return v;
    };
    const std::string& kind = next();
    if (kind == "d") {
      result.done.push_back(static_cast<int>(integer(0, 1 << 30)));
    } else if (kind == "r") {
      const int point = static_cast<int>(integer(0, 1 << 30));
      TrialRecord r;
      r.sweep = next();
      r.value = real();
      r.algorithm = next();
      r.trial = static_cast<int>(integer(0, 1 << 30));
      const auto u64 = [&]() {
        const std::string& t = next();
        if (t.empty() || !std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; }))
          throw common::InputError(where + ": '" + t + "' is not a seed");
        return static_cast<std::uint64_t>(std::stoull(t));
      };
      r.seed = u64();
      r.start_seed = u64();
      r.status = next();
      for (const Metric& m : kMetrics) {
        if (m.integer) {
          m.set(r, static_cast<double>(integer(0, 1LL << 31)));
        } else if (m.flag) {
          m.set(r, static_cast<double>(integer(0, 1)));
        } else {
          m.set(r, real());
        }
      }
      r.extra.resize(static_cast<std::size_t>(integer(0, 1 << 20)));
      for (double& v : r.extra) v = real();
      for (Eigen::Matrix3Xd* q : {&r.start_m, &r.final_m}) {
        q->resize(3, integer(0, 1 << 20));
        for (Eigen::Index n = 0; n < q->cols(); ++n) {
          for (int i = 0; i < 3; ++i) (*q)(i, n) = real();
        }
      }
      if (k != f.size()) throw common::InputError(where + ": " + std::to_string(f.size() - k) + " extra fields");
      result.points[point].push_back(std::move(r));
    } else {
      throw common::InputError(where + ": unknown line kind '" + kind + "'");
    }
  }
  return result;
}

}  // namespace losmimo::experiment
