#include "losmimo/placement/common/bounded_read.h"

#include <fstream>
#include <istream>

namespace losmimo::common {

std::string format_bytes(std::size_t bytes) {
  if (bytes >= (std::size_t{1} << 30) && bytes % (std::size_t{1} << 30) == 0)
    return std::to_string(bytes >> 30) + " GiB";
  if (bytes >= (std::size_t{1} << 20) && bytes % (std::size_t{1} << 20) == 0)
    return std::to_string(bytes >> 20) + " MiB";
  if (bytes >= (std::size_t{1} << 10) && bytes % (std::size_t{1} << 10) == 0)
    return std::to_string(bytes >> 10) + " KiB";
  return std::to_string(bytes) + " bytes";
}

std::string read_file_bounded(const std::string& path, std::size_t max_bytes, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open " + what);
  std::string text;
  constexpr std::size_t kChunk = 64 * 1024;
  std::string chunk(kChunk, '\0');
  while (in) {
    // Never more than max_bytes + 1: enough to tell "too large" without holding more.
    const std::size_t want = std::min(kChunk, max_bytes + 1 - text.size());
    in.read(chunk.data(), static_cast<std::streamsize>(want));
    text.append(chunk.data(), static_cast<std::size_t>(in.gcount()));
    if (text.size() > max_bytes) {
      throw InputError(path + ": " + what + " larger than " + format_bytes(max_bytes) + " (the limit)");
    }
    if (in.gcount() == 0) break;
  }
  // A directory opens but cannot be read: badbit (or failbit without eof).
  if (in.bad() || (in.fail() && !in.eof())) throw InputError(path + ": cannot read " + what);
  return text;
}

bool getline_bounded(std::istream& in, std::string& line, std::size_t max_line_bytes, const std::string& where) {
  line.clear();
  std::istream::sentry ok(in, true);
  if (!ok) return false;
  std::streambuf* buf = in.rdbuf();
  bool any = false;
  while (true) {
    const int c = buf->sbumpc();
    if (c == std::char_traits<char>::eof()) {
      in.setstate(std::ios::eofbit);
      if (!any) in.setstate(std::ios::failbit);
      return any;
    }
    any = true;
    if (c == '\n') return true;
    if (line.size() >= max_line_bytes) {
      throw InputError(where + ": line longer than " + format_bytes(max_line_bytes) + " (the limit)");
    }
    line.push_back(static_cast<char>(c));
  }
}

}  // namespace losmimo::common
