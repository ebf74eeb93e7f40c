#pragma once
// The uncompressed byte stream under the rawlog reader (reader.h): a file through zlib's
// gzip reader (which also passes plain files through), or bytes in memory (inflated when they
// start with the gzip magic 1f 8b, else taken as they are). Trailing bytes after a complete
// gzip member are ignored, as gzread does; the gzip CRC is checked at its end.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

namespace losmimo::rawlog_io {

// A truncated (the gzip stream ends early) or corrupt (bad deflate data, CRC) stream.
class RawlogSourceError : public std::runtime_error {
 public:
  RawlogSourceError(const std::string& what, bool is_truncated) : std::runtime_error(what), truncated(is_truncated) {}
  bool truncated;
};

class RawlogByteSource {
 public:
  virtual ~RawlogByteSource() = default;
  // Up to n bytes into dst; 0 at a clean end. Throws RawlogSourceError.
  virtual std::size_t read(std::uint8_t* dst, std::size_t n) = 0;
};

// Throws std::runtime_error("<path>: cannot open rawlog") if the file cannot be opened.
std::unique_ptr<RawlogByteSource> open_rawlog_file_source(const std::string& path);
std::unique_ptr<RawlogByteSource> make_rawlog_memory_source(std::string bytes);

}  // namespace losmimo::rawlog_io
