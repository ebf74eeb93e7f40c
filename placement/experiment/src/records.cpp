#include "losmimo/placement/experiment/records.h"

#include <algorithm>
#include <cstdlib>
#include <istream>
#include <optional>
#include <ostream>
#include <sstream>

#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/hash.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/experiment/metrics.h"

namespace losmimo::experiment {

using common::InputError;

namespace {
// Full precision (round trip): the checkpoint and shard records.

void write_matrix(std::ostream& out, const Eigen::Matrix3Xd& q) {
  out << "," << q.cols();
  for (Eigen::Index n = 0; n < q.cols(); ++n) {
    for (int i = 0; i < 3; ++i) out << "," << common::format_exact(q(i, n));
  }
}

std::string record_text(int point, const TrialRecord& r) {
  std::ostringstream out;
  out << "r," << point << "," << r.sweep << "," << common::format_exact(r.value) << "," << r.algorithm << "," << r.trial
      << "," << r.seed << "," << r.start_seed << "," << r.status;
  for (const Metric& m : kMetrics) out << "," << common::format_exact(m.get(r));
  out << "," << r.extra.size();
  for (const double v : r.extra) out << "," << common::format_exact(v);
  write_matrix(out, r.start_m);
  write_matrix(out, r.final_m);
  return out.str();
}

std::string hex(std::uint64_t v) { return common::format_hex64(v); }

// "(point 3, trial 2, gd)": a record as messages name it.
std::string name_of(int point, const TrialRecord& r) {
  return "(point " + std::to_string(point) + ", trial " + std::to_string(r.trial) + ", " + r.algorithm + ")";
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> f;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    f.push_back(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return f;
}

// Parses an r line's fields (without its digest) into a record; InputError naming `where`.
TrialRecord parse_record(const std::vector<std::string>& f, std::size_t count, int& point, const std::string& where) {
  std::size_t k = 1;  // f[0] is "r"
  const auto next = [&]() -> const std::string& {
    if (k >= count) throw InputError(where + ": too few fields");
    return f[k++];
  };
  const auto integer = [&](long long lo, long long hi) { return common::parse_integer(next(), where, lo, hi); };
  const auto real = [&]() {
    const std::string& t = next();
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (t.empty() || end != t.c_str() + t.size()) throw InputError(where + ": '" + t + "' is not a number");
    return v;
  };
  const auto u64 = [&]() {
    const std::string& t = next();
    if (t.empty() || t.size() > 20 || !std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; }))
      throw InputError(where + ": '" + t + "' is not a seed");
    return static_cast<std::uint64_t>(std::stoull(t));
  };
  point = static_cast<int>(integer(0, 1 << 30));
  TrialRecord r;
  r.sweep = next();
  r.value = real();
  r.algorithm = next();
  r.trial = static_cast<int>(integer(0, 1 << 30));
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
  // Counts are bounded by the fields actually on the line before anything is allocated.
  r.extra.resize(static_cast<std::size_t>(integer(0, static_cast<long long>(count - k))));
  for (double& v : r.extra) v = real();
  for (Eigen::Matrix3Xd* q : {&r.start_m, &r.final_m}) {
    q->resize(3, integer(0, static_cast<long long>(count - k) / 3));
    for (Eigen::Index n = 0; n < q->cols(); ++n) {
      for (int i = 0; i < 3; ++i) (*q)(i, n) = real();
    }
  }
  if (k != count) throw InputError(where + ": " + std::to_string(count - k) + " extra fields");
  return r;
}

std::uint64_t parse_hex(const std::string& t, const std::string& where) {
  if (t.size() != 16 || !std::all_of(t.begin(), t.end(), [](char c) {
        return std::isxdigit(static_cast<unsigned char>(c)) && !std::isupper(static_cast<unsigned char>(c));
      }))
    throw InputError(where + ": '" + t + "' is not a digest (16 hex digits)");
  return std::stoull(t, nullptr, 16);
}

}  // namespace

std::string RecordsWriter::emit(std::string text) {
  digest_ = common::fnv1a64(text, digest_);
  return text;
}

std::string RecordsWriter::header(const RecordsHeader& h) {
  digest_ = common::kFnvOffset;
  points_ = 0;
  records_ = 0;
  std::string text = emit(std::string(kRecordsHeader) + "\n");
  return text + emit("h," + h.kind + "," + std::to_string(h.shard_index) + "," + std::to_string(h.shard_count) + "," +
                     hex(h.config_digest) + "\n");
}

std::string RecordsWriter::point(int point, const std::vector<TrialRecord>& records) {
  std::string text;
  for (const TrialRecord& r : records) {
    const std::string line = record_text(point, r);
    text += emit(line + "," + hex(common::fnv1a64(line)) + "\n");
  }
  records_ += static_cast<std::int64_t>(records.size());
  ++points_;
  return text + emit("d," + std::to_string(point) + "," + std::to_string(records.size()) + "," + hex(digest_) + "\n");
}

std::string RecordsWriter::end() {
  return emit("e," + std::to_string(points_) + "," + std::to_string(records_) + "," + hex(digest_) + "\n");
}

namespace {

// One records file read line by line: the running digest, the point under way and what has
// been verified so far.
class RecordsReader {
 public:
  RecordsReader(const std::string& origin, RecordsMode mode)
      : origin_(origin), checkpoint_(mode == RecordsMode::kCheckpoint) {}
  RecordLines read(std::istream& in, std::size_t max_line_bytes);

 private:
  void magic_line(const std::string& line, const std::string& where) const;
  void header_line(const std::vector<std::string>& f, const std::string& where);
  void record_line(const std::string& line, const std::vector<std::string>& f, const std::string& where);
  void mark_line(const std::vector<std::string>& f, std::uint64_t digest_before, const std::string& where);
  void point_end(const std::vector<std::string>& f, long long n, std::uint64_t stated, std::uint64_t digest_before,
                 const std::string& where);
  void file_end(const std::vector<std::string>& f, long long n, std::uint64_t stated, std::uint64_t digest_before,
                const std::string& where);
  void finish(const std::istream& in);

  const std::string& origin_;
  const bool checkpoint_;
  RecordLines result_;
  std::uint64_t digest_ = common::kFnvOffset;
  std::uint64_t bytes_ = 0;
  int line_no_ = 0;
  bool header_seen_ = false, ended_ = false;
  int next_point_ = 0;
  // The point being read: its records and, per (trial, algorithm), the line it came from.
  std::vector<TrialRecord> pending_;
  std::map<std::pair<int, std::string>, int> pending_lines_;
};

RecordLines RecordsReader::read(std::istream& in, std::size_t max_line_bytes) {
  std::string line;
  while (true) {
    const std::string where = origin_ + ":" + std::to_string(line_no_ + 1);
    if (!common::getline_bounded(in, line, max_line_bytes, where)) break;
    ++line_no_;
    if (in.eof()) {
      // No end of line: the write was cut here (lines are written whole and in order, so only
      // the last one can be). A checkpoint ends at its last complete point anyway.
      if (!checkpoint_) throw InputError(where + ": truncated last line (no end of line)");
      ++result_.unverified_lines;
      break;
    }
    const std::string text = line + "\n";
    const std::uint64_t digest_before = digest_;
    digest_ = common::fnv1a64(text, digest_);
    bytes_ += text.size();
    if (line_no_ == 1) {
      magic_line(line, where);
      continue;
    }
    if (ended_) throw InputError(where + ": a line after the e line that closes the file");
    const std::vector<std::string> f = split(line);
    const std::string& kind = f[0];
    if (!header_seen_) {
      header_line(f, where);
    } else if (kind == "r") {
      record_line(line, f, where);
    } else if (kind == "d" || kind == "e") {
      mark_line(f, digest_before, where);
    } else {
      throw InputError(where + ": unknown line kind '" + kind + "'");
    }
  }
  finish(in);
  return std::move(result_);
}

void RecordsReader::magic_line(const std::string& line, const std::string& where) const {
  if (line.rfind(kRecordsMagic, 0) == 0 && line != kRecordsHeader) {
    throw InputError(where + ": '" + line + "': written by another losmimo version (expected '" + kRecordsHeader +
                     "'); run that experiment again");
  }
  if (line != kRecordsHeader) throw InputError(where + ": not a records file (expected '" + kRecordsHeader + "')");
}

void RecordsReader::header_line(const std::vector<std::string>& f, const std::string& where) {
  if (f[0] != "h" || f.size() != 5) {
    throw InputError(where + ": expected the h line (h,<kind>,<index>,<count>,<config digest>)");
  }
  RecordsHeader& h = result_.header;
  h.kind = f[1];
  if (h.kind != kRecordsKindRun && h.kind != kRecordsKindShard)
    throw InputError(where + ": unknown kind '" + h.kind + "'");
  h.shard_count = static_cast<int>(common::parse_integer(f[3], where, 1, 1'000'000'000));
  h.shard_index = static_cast<int>(common::parse_integer(f[2], where, 0, h.shard_count - 1));
  h.config_digest = parse_hex(f[4], where);
  header_seen_ = true;
  result_.verified_bytes = bytes_;
}

void RecordsReader::record_line(const std::string& line, const std::vector<std::string>& f, const std::string& where) {
  if (f.size() < 2) throw InputError(where + ": too few fields");
  int point = 0;
  TrialRecord r = parse_record(f, f.size() - 1, point, where);
  if (parse_hex(f.back(), where) != common::fnv1a64(std::string_view(line).substr(0, line.rfind(',')))) {
    throw InputError(where + ": record " + name_of(point, r) + " was altered: its digest does not match its text");
  }
  if (point != next_point_) {
    throw InputError(where + ": record " + name_of(point, r) + " where point " + std::to_string(next_point_) +
                     " is under way (a d line missing or a record moved)");
  }
  const auto [it, fresh] = pending_lines_.emplace(std::make_pair(r.trial, r.algorithm), line_no_);
  if (!fresh) {
    throw InputError(where + ": record " + name_of(point, r) + " appears twice (also line " +
                     std::to_string(it->second) + ")");
  }
  pending_.push_back(std::move(r));
}

// A d or e line: <kind>,<point or points>,<records>,<digest of the file before this line>.
void RecordsReader::mark_line(const std::vector<std::string>& f, std::uint64_t digest_before,
                              const std::string& where) {
  const std::string& kind = f[0];
  if (f.size() != 4) throw InputError(where + ": expected " + kind + ",<point>,<records>,<digest>");
  const long long n = common::parse_integer(f[2], where, 0, 1LL << 40);
  const std::uint64_t stated = parse_hex(f[3], where);
  if (kind == "d") {
    point_end(f, n, stated, digest_before, where);
  } else {
    file_end(f, n, stated, digest_before, where);
  }
}

void RecordsReader::point_end(const std::vector<std::string>& f, long long n, std::uint64_t stated,
                              std::uint64_t digest_before, const std::string& where) {
  const int point = static_cast<int>(common::parse_integer(f[1], where, 0, 1 << 30));
  if (point != next_point_) {
    throw InputError(where + ": point " + std::to_string(point) + " finished where point " +
                     std::to_string(next_point_) + " was expected (a point missing or repeated)");
  }
  if (static_cast<long long>(pending_.size()) != n) {
    throw InputError(where + ": point " + std::to_string(point) + " has " + std::to_string(pending_.size()) +
                     " records where its d line says " + std::to_string(n) + " (a record " +
                     (static_cast<long long>(pending_.size()) < n ? "missing" : "added") + ")");
  }
  if (stated != digest_before) {
    throw InputError(where + ": point " + std::to_string(point) +
                     ": the digest of the file up to here differs from its d line (a line changed, added or removed)");
  }
  result_.points[point] = std::move(pending_);
  result_.records += n;
  pending_.clear();
  pending_lines_.clear();
  ++next_point_;
  result_.verified_bytes = bytes_;
}

void RecordsReader::file_end(const std::vector<std::string>& f, long long n, std::uint64_t stated,
                             std::uint64_t digest_before, const std::string& where) {
  if (checkpoint_) throw InputError(where + ": an e line in a checkpoint");
  const long long points = common::parse_integer(f[1], where, 0, 1 << 30);
  if (!pending_.empty()) throw InputError(where + ": point " + std::to_string(next_point_) + " was not finished");
  if (points != next_point_ || n != result_.records || stated != digest_before) {
    throw InputError(where + ": the e line says " + f[1] + " points, " + f[2] + " records and digest " + f[3] +
                     "; the file holds " + std::to_string(next_point_) + " points, " + std::to_string(result_.records) +
                     " records, digest " + hex(digest_before));
  }
  ended_ = true;
}

void RecordsReader::finish(const std::istream& in) {
  if (in.bad()) throw InputError(origin_ + ": read error");
  if (!header_seen_) throw InputError(origin_ + ": no h line (an empty or cut records file)");
  if (!checkpoint_ && !ended_) {
    throw InputError(origin_ + ": no e line: the file is cut short (" + std::to_string(next_point_) + " points, " +
                     std::to_string(result_.records) + " records verified)");
  }
  result_.unverified_lines += static_cast<int>(pending_.size());
}

}  // namespace

RecordLines read_records(std::istream& in, const std::string& origin, RecordsMode mode, std::size_t max_line_bytes) {
  return RecordsReader(origin, mode).read(in, max_line_bytes);
}

void check_point_jobs(const std::string& origin, int point, const std::vector<TrialRecord>& records,
                      const std::set<int>& trials) {
  std::set<std::string> algorithms;
  std::map<int, std::map<std::string, int>> seen;
  for (const TrialRecord& r : records) {
    algorithms.insert(r.algorithm);
    if (!trials.count(r.trial)) {
      throw InputError(origin + ": record " + name_of(point, r) + " is not one of this folder's jobs");
    }
    if (++seen[r.trial][r.algorithm] > 1) throw InputError(origin + ": record " + name_of(point, r) + " appears twice");
  }
  for (const int t : trials) {
    for (const std::string& a : algorithms) {
      if (!seen[t].count(a)) {
        throw InputError(origin + ": point " + std::to_string(point) + ", trial " + std::to_string(t) +
                         ": no record of algorithm " + a + " (a record missing)");
      }
    }
    if (algorithms.empty()) {
      throw InputError(origin + ": point " + std::to_string(point) + ", trial " + std::to_string(t) + ": no records");
    }
  }
}

}  // namespace losmimo::experiment
