#include "losmimo/placement/common/gnuplot.h"

#include <cstdlib>
#include <filesystem>

namespace losmimo::common {

std::vector<std::string> render_gnuplot(const std::string& dir, const std::vector<std::string>& stems,
                                        const std::string& what_was_written) {
  std::vector<std::string> warnings;
  if (stems.empty()) return warnings;
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
    warnings.push_back("gnuplot not found: " + what_was_written);
    return warnings;
  }
  for (const std::string& stem : stems) {
    const std::string cmd = "cd '" + dir + "' && gnuplot " + stem + ".gp 2> " + stem + ".log";
    if (std::system(cmd.c_str()) != 0) {
      warnings.push_back("gnuplot failed on " + stem + ".gp (see " + stem + ".log)");
    } else {
      std::filesystem::remove(std::filesystem::path(dir) / (stem + ".log"));
    }
  }
  return warnings;
}

}  // namespace losmimo::common
