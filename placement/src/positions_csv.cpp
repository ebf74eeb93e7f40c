#include "losmimo/placement/common/bounded_read.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/positions_csv.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <fstream>
#include <sstream>
#include <vector>

namespace losmimo::placement {

namespace {
constexpr double kMaxAbsCoordinate_m = 1e9;

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

std::string strip(const std::string& s) {
  const std::size_t b = s.find_first_not_of(" \t\r");
  const std::size_t e = s.find_last_not_of(" \t\r");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}
}  // namespace

namespace {

// The header's columns: x, y, z and the others (e.g. sweep, trial, stage) by position.
struct Columns {
  std::vector<std::string> names;
  int x = 0, y = 1, z = 2;
  bool plain() const { return names.size() == 3; }
  int index_of(const std::string& name) const {
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return static_cast<int>(i);
    return -1;
  }
};

// A header names x, y and z (no field parses as a number).
std::optional<Columns> header_of(const std::vector<std::string>& fields) {
  Columns c;
  for (const std::string& f : fields) c.names.push_back(strip(f));
  c.x = c.index_of("x");
  c.y = c.index_of("y");
  c.z = c.index_of("z");
  if (c.x < 0 || c.y < 0 || c.z < 0) return std::nullopt;
  return c;
}

bool same_value(const std::string& a, const std::string& b) {
  if (a == b) return true;
  char* end_a = nullptr;
  char* end_b = nullptr;
  const double x = std::strtod(a.c_str(), &end_a), y = std::strtod(b.c_str(), &end_b);
  return !a.empty() && !b.empty() && *end_a == '\0' && *end_b == '\0' && x == y;
}

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& i : items) out += (out.empty() ? "" : ", ") + i;
  return out;
}

}  // namespace

Eigen::Matrix3Xd parse_positions_csv(std::istream& in, const std::string& origin, int max_rows,
                                     const PositionsSelection& selection) {
  static const char* const kFieldNames[3] = {"x", "y", "z"};
  Columns columns{{"x", "y", "z"}};
  std::vector<Eigen::Vector3d> rows;
  // Per column that is neither a coordinate, uav nor selected: the values the selected rows hold.
  std::vector<std::vector<std::string>> free_values;
  std::vector<int> selected_index;
  std::string line;
  int line_no = 0;
  bool seen_data = false;
  const auto check_selection = [&](const std::string& where) {
    for (const auto& [column, value] : selection) {
      const int i = columns.index_of(column);
      if (i < 0 || i == columns.x || i == columns.y || i == columns.z) {
        throw common::InputError(where + ": no column '" + column + "' to select " + column + "=" + value +
                                 " by (columns: " + joined(columns.names) + ")");
      }
      selected_index.push_back(i);
    }
    free_values.assign(columns.names.size(), {});
  };
  while (
      common::getline_bounded(in, line, common::kMaxPositionsLineBytes, origin + ":" + std::to_string(line_no + 1))) {
    ++line_no;
    const std::string where = origin + ":" + std::to_string(line_no);
    // A UTF-8 byte-order mark (written by some editors) is not part of the first field.
    if (line_no == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
    const std::string content = strip(line);
    if (content.empty() || content.front() == '#') continue;
    const std::vector<std::string> fields = split_fields(content);
    if (!seen_data) {
      seen_data = true;
      if (const std::optional<Columns> header = header_of(fields)) {
        columns = *header;
        check_selection(where);
        continue;
      }
      check_selection(origin + ":" + std::to_string(line_no) + " (no header: x,y,z)");
    }
    if (fields.size() != columns.names.size()) {
      throw common::InputError(where + ": expected " + std::to_string(columns.names.size()) + " fields " +
                               joined(columns.names) + ", got " + std::to_string(fields.size()));
    }
    bool selected = true;
    for (std::size_t k = 0; k < selection.size() && selected; ++k)
      selected = same_value(strip(fields[selected_index[k]]), selection[k].second);
    if (!selected) continue;
    if (static_cast<int>(rows.size()) >= max_rows) {
      throw common::InputError(where + ": more than " + std::to_string(max_rows) + " positions");
    }
    Eigen::Vector3d q;
    const int index[3] = {columns.x, columns.y, columns.z};
    for (int i = 0; i < 3; ++i) {
      const std::string field_where = where + ": field " + kFieldNames[i];
      q(i) = common::parse_double(fields[index[i]], field_where, kFieldNames[i]);
      // Beyond this, distances overflow (|q| ~ 1e154 m) or phases lose all precision.
      if (!(std::abs(q(i)) <= kMaxAbsCoordinate_m)) {
        throw common::InputError(field_where + ": " + strip(fields[index[i]]) + " is out of range [-1e9, 1e9] m",
                                 kFieldNames[i]);
      }
    }
    rows.push_back(q);
    for (std::size_t i = 0; i < columns.names.size(); ++i) {
      const int c = static_cast<int>(i);
      if (c == columns.x || c == columns.y || c == columns.z || columns.names[i] == "uav") continue;
      if (std::find(selected_index.begin(), selected_index.end(), c) != selected_index.end()) continue;
      std::vector<std::string>& seen = free_values[i];
      const std::string v = strip(fields[i]);
      if (seen.size() < 9 && std::find(seen.begin(), seen.end(), v) == seen.end()) seen.push_back(v);
    }
  }
  if (in.bad()) throw common::InputError(origin + ": read error");
  if (rows.empty()) {
    std::string what;
    for (const auto& [column, value] : selection) what += (what.empty() ? "" : ", ") + column + "=" + value;
    throw common::InputError(origin + ": no positions" + (what.empty() ? "" : " with " + what));
  }
  // A table of several swarms: the selection must leave one.
  std::string choices;
  for (std::size_t i = 0; i < free_values.size(); ++i) {
    if (free_values[i].size() > 1) {
      choices += (choices.empty() ? "" : "; ") + columns.names[i] + ": " + joined(free_values[i]) +
                 (free_values[i].size() > 8 ? ", ..." : "");
    }
  }
  if (!choices.empty()) {
    throw common::InputError(origin + ": holds several swarms; pick one with --select column=value (" + choices + ")");
  }
  Eigen::Matrix3Xd q(3, rows.size());
  for (std::size_t n = 0; n < rows.size(); ++n) q.col(n) = rows[n];
  return q;
}

Eigen::Matrix3Xd read_positions_csv(const std::string& path, int max_rows, const PositionsSelection& selection) {
  std::istringstream in(common::read_file_bounded(path, common::kMaxPositionsBytes, "positions file"));
  return parse_positions_csv(in, path, max_rows, selection);
}

}  // namespace losmimo::placement
