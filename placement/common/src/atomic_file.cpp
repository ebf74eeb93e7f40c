#include "losmimo/placement/common/atomic_file.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace losmimo::common {

void write_stream_atomically(const std::string& path, const std::function<void(std::ostream&)>& writer) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    writer(out);
    out.flush();
    if (!out) throw std::runtime_error(tmp + ": write failed");
  }
  std::filesystem::rename(tmp, path);
}

void write_file_atomically(const std::string& path, const std::string& content) {
  write_stream_atomically(path, [&](std::ostream& out) { out << content; });
}

}  // namespace losmimo::common
