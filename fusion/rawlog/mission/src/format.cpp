#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/hash.h"
#include "losmimo/fusion/rawlog/mission/format.h"
#include "losmimo/fusion/rawlog/io/labels.h"

#include <cstdlib>
#include <sstream>

#include "losmimo/placement/run.h"

namespace losmimo::rawlog {

namespace {
constexpr const char* kStreamNames[] = {"TRUTH",  "DR",      "BEACON", "BEACON64", "CSI",
                                        "BELIEF", "REFINED", "MOVE",   "ODOMETRY", "BS_RANGES"};
constexpr int kNumStreams = sizeof(kStreamNames) / sizeof(kStreamNames[0]);
}  // namespace

std::string to_string(UavStream stream) { return kStreamNames[static_cast<int>(stream)]; }

std::string uav_label(int uav, UavStream stream) { return rawlog_io::uav_label(uav, to_string(stream)); }

std::optional<UavLabel> parse_uav_label(const std::string& label) {
  const std::optional<rawlog_io::UavLabelParts> parts = rawlog_io::split_uav_label(label);
  if (!parts) return std::nullopt;
  UavLabel out;
  out.uav = parts->uav;
  out.suffix = parts->suffix;
  for (int s = 0; s < kNumStreams; ++s) {
    if (out.suffix == kStreamNames[s]) out.stream = static_cast<UavStream>(s);
  }
  return out;
}

std::string with_text_digest(const std::string& text) {
  return text + "text_digest = " + common::format_hex64(common::fnv1a64(text)) + "\n";
}

bool text_digest_matches(const std::string& text) {
  const auto last = text.rfind("text_digest = ");
  return last != std::string::npos && with_text_digest(text.substr(0, last)) == text;
}

std::map<std::string, std::string> parse_mark_keys(const std::string& text) {
  std::map<std::string, std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const auto eq = line.find(" = ");
    if (eq != std::string::npos) out[line.substr(0, eq)] = line.substr(eq + 3);
  }
  return out;
}

bool is_fault_status(const std::string& status) {
  return status == placement::to_string(placement::RunStatus::kUavUnresponsive) ||
         status == placement::to_string(placement::RunStatus::kNumericalFault);
}

std::string read_run_end(const std::map<std::string, std::string>& keys, int num_uavs, RunEnd& out) {
  const auto get = [&](const char* key) -> std::optional<std::string> {
    const auto it = keys.find(key);
    return it == keys.end() ? std::nullopt : std::optional<std::string>(it->second);
  };
  const std::string status = get("status").value_or("");
  bool known = false;
  for (const placement::RunStatus s : {placement::RunStatus::kConverged, placement::RunStatus::kIterationCap,
                                       placement::RunStatus::kUavUnresponsive, placement::RunStatus::kNumericalFault})
    known = known || status == placement::to_string(s);
  if (!known)
    return "status = '" + status + "': not a run status (converged, iteration_cap, uav_unresponsive, numerical_fault)";
  const bool fault = is_fault_status(status);
  RunEnd end{status, -1, get("fault").value_or("")};
  if (const std::optional<std::string> uav = get("fault_uav")) {
    char* stop = nullptr;
    const long v = std::strtol(uav->c_str(), &stop, 10);
    if (!fault || uav->empty() || *stop != '\0' || v < -1 || v >= num_uavs)
      return "fault_uav = '" + *uav + "': not a UAV index in [-1, " + std::to_string(num_uavs - 1) +
             "] of a faulted run";
    end.fault_uav = static_cast<int>(v);
  }
  if (!fault && get("fault")) return "fault = '" + end.fault + "' with status = " + status;
  out = end;
  return "";
}

}  // namespace losmimo::rawlog
