#pragma once
// Renders gnuplot scripts: for each stem, `gnuplot <stem>.gp` in `dir` (the script names its
// own output, e.g. <stem>.png). gnuplot (Debian gnuplot-nox) is optional: without it on PATH the
// scripts stay for the user and one warning says so. Returns the warnings (a missing gnuplot, or
// a script that failed: its stderr is kept in <stem>.log).

#include <string>
#include <vector>

namespace losmimo::common {

std::vector<std::string> render_gnuplot(const std::string& dir, const std::vector<std::string>& stems,
                                        const std::string& what_was_written);

}  // namespace losmimo::common
