#pragma once
// Files that are either complete or absent: the content goes to `<path>.tmp`, is flushed, and
// is renamed over `path` (rename is atomic on one POSIX file system). A failed write throws
// std::runtime_error naming the temporary file and leaves `path` as it was.

#include <functional>
#include <iosfwd>
#include <string>

namespace losmimo::common {

void write_file_atomically(const std::string& path, const std::string& content);
void write_stream_atomically(const std::string& path, const std::function<void(std::ostream&)>& writer);

}  // namespace losmimo::common
