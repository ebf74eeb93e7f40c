#include "losmimo/fusion/rawlog/io/labels.h"

#include <cctype>
#include <cstdio>

namespace losmimo::rawlog_io {

std::string uav_label(int uav, const std::string& suffix) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "UAV%02d_", uav);
  return buf + suffix;
}

std::optional<UavLabelParts> split_uav_label(const std::string& label) {
  if (label.size() < 6 || label.compare(0, 3, "UAV") != 0) return std::nullopt;
  std::size_t i = 3;
  long uav = 0;
  while (i < label.size() && std::isdigit(static_cast<unsigned char>(label[i]))) {
    if (i - 3 >= 5) return std::nullopt;  // uav < 100000
    uav = uav * 10 + (label[i] - '0');
    ++i;
  }
  if (i == 3 || i >= label.size() || label[i] != '_' || i + 1 == label.size()) return std::nullopt;
  UavLabelParts out;
  out.uav = static_cast<int>(uav);
  out.suffix = label.substr(i + 1);
  return out;
}

}  // namespace losmimo::rawlog_io
