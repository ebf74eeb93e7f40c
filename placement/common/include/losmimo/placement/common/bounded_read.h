#pragma once
// Reading input whose size nobody vouches for: every reader of user files goes through these,
// so `/dev/zero`, a FIFO or a multi-gigabyte file is refused with a clear message instead of
// growing until memory runs out.
//   read_file_bounded   a whole file of at most max_bytes (reads at most max_bytes + 1)
//   getline_bounded     one line of at most max_line_bytes (the '\n' excluded)
// Both throw InputError naming the file (and line) and the limit.

#include <cstddef>
#include <iosfwd>
#include <string>

#include "losmimo/placement/common/input_error.h"

namespace losmimo::common {

// The limits of the inputs losmimo reads (docs/reliability.md, "Size limits"). Each is far
// above the largest legitimate input (in brackets).
inline constexpr std::size_t kMaxConfigBytes = std::size_t{1} << 20;      // INI files [paper.ini 1.2 KB]
inline constexpr std::size_t kMaxPositionsBytes = std::size_t{16} << 20;  // positions CSV [65536 UAVs: 5 MB]
inline constexpr std::size_t kMaxPositionsLineBytes = 4096;               // [a UAV at %.17g: 75 B]
inline constexpr std::size_t kMaxRecordLineBytes = std::size_t{1} << 20;  // [4096 UAVs: 650 KB]
inline constexpr std::size_t kMaxRecordsBytes = std::size_t{1} << 30;     // all records of a run [paper run: 108 MB]

// "1 MiB", "4096 bytes": a limit as messages show it.
std::string format_bytes(std::size_t bytes);

// `what` names the input in messages ("config file", "positions file").
std::string read_file_bounded(const std::string& path, std::size_t max_bytes, const std::string& what);

// Reads the next line into `line` (a trailing '\r' kept); false at the end of the stream. A line
// longer than max_line_bytes throws InputError("<where>: line longer than ..."), without
// reading the rest of it.
bool getline_bounded(std::istream& in, std::string& line, std::size_t max_line_bytes, const std::string& where);

}  // namespace losmimo::common
