#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/hash.h"
#include "losmimo/placement/common/ini_config.h"
#include "losmimo/fusion/rawlog/mission/log.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRawDAQ.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>

#include "losmimo/fusion/rawlog/mission/format.h"
#include "losmimo/placement/common/input_error.h"

namespace losmimo::rawlog {

namespace {

using mrpt::obs::CObservation;
constexpr int kMaxUavs = 4096;  // placement's num_uavs bound
constexpr int kMaxEpochs = 10'000'000;
constexpr int kMaxForeignUavs = 256;  // foreign labels above UAV255_ are skipped

// Marks start with "losmimo <LABEL>\n" (recorder.cpp).
bool is_mark(const mrpt::obs::CObservationComment& c, const char* label) {
  const std::string head = std::string("losmimo ") + label + "\n";
  return c.text.compare(0, head.size(), head) == 0;
}

// A decimal uint64 (surrounding spaces allowed); common::InputError otherwise.
std::uint64_t parse_u64(const std::string& text, const std::string& where) {
  const auto b = text.find_first_not_of(' ');
  const auto e = text.find_last_not_of(' ');
  const std::string t = b == std::string::npos ? "" : text.substr(b, e - b + 1);
  std::uint64_t v = 0;
  for (char c : t) {
    const unsigned d = static_cast<unsigned>(c - '0');
    if (d > 9 || v > (std::numeric_limits<std::uint64_t>::max() - d) / 10)
      throw common::InputError(where + ": '" + t + "' is not a 64-bit unsigned integer");
    v = v * 10 + d;
  }
  if (t.empty()) throw common::InputError(where + ": empty entry");
  return v;
}

bool all_finite(const std::vector<double>& v) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

localization::Belief belief_of(const mrpt::obs::CObservationRobotPose& o) {
  localization::Belief b;
  b.mean_m = Eigen::Vector3d(o.pose.mean.x(), o.pose.mean.y(), o.pose.mean.z());
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) b.cov_m2(i, j) = o.pose.cov(i, j);
  return b;
}

class Builder {
 public:
  explicit Builder(MissionLog& log) : log_(log) {}

  void add(const rawlog_io::RawlogObject& o) {
    if (o.index == 0) detect_ours(o);
    if (log_.ours) {
      add_ours(o);
    } else {
      add_foreign(*o.object, o.class_name);
    }
  }

  void finish() {
    if (log_.ours) log_.objects_after_last_mark = static_cast<std::int64_t>(pending_.size());
  }

 private:
  struct Pending {
    std::string class_name;
    std::shared_ptr<mrpt::serialization::CSerializable> object;
  };

  void detect_ours(const rawlog_io::RawlogObject& o) {
    const auto* c = dynamic_cast<const mrpt::obs::CObservationComment*>(o.object.get());
    const std::string magic = std::string(kRawlogMagic) + " ";
    // (MRPT 2.5 does not store a comment's sensorLabel: the text says what it is.)
    if (!c || c->text.compare(0, magic.size(), magic) != 0) return;
    log_.ours = true;
    const std::string& text = c->text;
    const auto body = text.find('\n');
    const auto split = text.find("\n[rawlog]\n");
    if (body == std::string::npos || split == std::string::npos)
      throw common::InputError("rawlog CONFIG: no [rawlog] section");
    log_.format_version = format_version(text.substr(magic.size(), body - magic.size()));
    log_.config_text = text.substr(body + 1, split - body);
    log_.config = load_mission_config(common::IniConfig::from_string(log_.config_text, "rawlog CONFIG"));
    const common::IniConfig raw = common::IniConfig::from_string(text.substr(split + 1), "rawlog CONFIG [rawlog]");
    if (raw.get_integer("rawlog", "format_version", log_.format_version, 0, 1000000) != log_.format_version)
      throw common::InputError("rawlog CONFIG: [rawlog] format_version differs from the header's " +
                               std::to_string(log_.format_version));
    log_.num_uavs = static_cast<int>(raw.get_integer("rawlog", "num_uavs", 0, 1, kMaxUavs));
    if (log_.num_uavs != log_.config->placement.scenario.num_uavs)
      throw common::InputError("rawlog CONFIG: [rawlog] num_uavs differs from [scenario] num_uavs");
    std::istringstream seeds(raw.get_string("rawlog", "filter_seeds", ""));
    for (std::string s; std::getline(seeds, s, ',') && log_.filter_seeds.size() <= kMaxUavs;) {
      log_.filter_seeds.push_back(parse_u64(s, "rawlog CONFIG [rawlog] filter_seeds"));
    }
    if (static_cast<int>(log_.filter_seeds.size()) != log_.num_uavs)
      throw common::InputError("rawlog CONFIG: filter_seeds has " + std::to_string(log_.filter_seeds.size()) +
                               " entries for " + std::to_string(log_.num_uavs) + " UAVs");
  }

  // The header line's version ("losmimo-rawlog <version>"): one this reader knows, or an error
  // naming it.
  static int format_version(const std::string& text) {
    std::size_t used = 0;
    int v = -1;
    try {
      v = std::stoi(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != text.size())
      throw common::InputError("rawlog CONFIG: format version '" + text + "' is not a number");
    if (v > kRawlogFormatVersion)
      throw common::InputError("rawlog CONFIG: format version " + std::to_string(v) +
                               " is newer than this losmimo reads (" + std::to_string(kOldestRawlogFormatVersion) +
                               " to " + std::to_string(kRawlogFormatVersion) + "): use a newer losmimo-replay");
    if (v < kOldestRawlogFormatVersion)
      throw common::InputError("rawlog CONFIG: format version " + std::to_string(v) +
                               " is not a losmimo rawlog version (" + std::to_string(kOldestRawlogFormatVersion) +
                               " to " + std::to_string(kRawlogFormatVersion) + ")");
    return v;
  }

  void add_ours(const rawlog_io::RawlogObject& o) {
    const auto* obs = dynamic_cast<const CObservation*>(o.object.get());
    if (!log_.integrity_error.empty() || log_.complete) {  // past a failed or final mark
      ++log_.objects_after_last_mark;
      return;
    }
    const auto* c = dynamic_cast<const mrpt::obs::CObservationComment*>(obs);
    if (c && (is_mark(*c, kLabelEpochEnd) || is_mark(*c, kLabelEndOfLog))) {
      check_mark(o, *c);
      return;
    }
    digest_ = common::fnv1a64(o.bytes.data(), o.bytes.size(), digest_);
    ++labels_seen_[o.index == 0 ? std::string(kLabelConfig) : (obs ? obs->sensorLabel : o.class_name)];
    if (o.index == 0) return;  // CONFIG
    pending_.push_back({o.class_name, o.object});
  }

  void check_mark(const rawlog_io::RawlogObject& o, const mrpt::obs::CObservationComment& c) {
    const auto keys = parse_mark_keys(c.text);
    const auto get = [&](const std::string& k) {
      const auto it = keys.find(k);
      return it == keys.end() ? std::string() : it->second;
    };
    std::string error;
    if (!text_digest_matches(c.text))
      error = "the mark's text_digest does not match its text";
    else if (get("objects") != std::to_string(o.index))
      error = "object count " + get("objects") + " != " + std::to_string(o.index);
    else if (get("digest") != common::format_hex64(digest_))
      error = "digest " + get("digest") + " != " + common::format_hex64(digest_);
    digest_ = common::kFnvOffset;
    const bool end = is_mark(c, kLabelEndOfLog);
    int epoch = -1;
    if (error.empty()) {
      try {
        epoch = static_cast<int>(std::stol(end ? get("final_truth_epoch") : get("epoch")));
      } catch (const std::exception&) {
        error = "no epoch number";
      }
      const int expected = static_cast<int>(log_.epochs.size());
      if (error.empty() && !end && epoch != expected)
        error = "epoch " + std::to_string(epoch) + " where " + std::to_string(expected) + " was expected";
    }
    if (error.empty() && end) error = check_counts(keys);
    if (error.empty() && end) error = read_run_end(keys, log_.num_uavs, log_.run_end);
    if (!error.empty()) {
      log_.integrity_error = std::string(end ? kLabelEndOfLog : kLabelEpochEnd) + " mark at object " +
                             std::to_string(o.index) + ": " + error;
      log_.objects_after_last_mark = static_cast<std::int64_t>(pending_.size()) + 1;
      pending_.clear();
      return;
    }
    if (end) {
      commit_final(epoch);
      log_.complete = true;
    } else {
      commit_epoch(get("modes"));
      ++labels_seen_[kLabelEpochEnd];
    }
    pending_.clear();
  }

  // END_OF_LOG: the epochs, marks and per-label counts it lists against what was read.
  std::string check_counts(const std::map<std::string, std::string>& keys) const {
    const std::string n_epochs = std::to_string(log_.epochs.size());
    if (keys.count("epochs") == 0 || keys.at("epochs") != n_epochs) return "epochs != " + n_epochs;
    if (keys.count("marks") == 0 || keys.at("marks") != n_epochs) return "marks != " + n_epochs;
    std::map<std::string, std::int64_t> listed;
    for (const auto& [k, v] : keys) {
      if (k.rfind("count.", 0) != 0) continue;
      try {
        listed[k.substr(6)] = std::stoll(v);
      } catch (const std::exception&) {
        return k + " = '" + v + "': not a count";
      }
    }
    if (listed != labels_seen_) return "the per-label counts differ from the objects read";
    return "";
  }

  void commit_epoch(const std::string& modes) {
    // Every UAV that reports writes at least TRUTH, CSI and BELIEF per epoch, so a log has at
    // least as many records as UAV-epochs. An epoch may hold fewer records than UAVs (UAVs that
    // were silent, or the last epoch of a run a fault stopped part-way), but over the log so far
    // fewer records than UAV-epochs, or an epoch with no record, is a damaged log. The check
    // keeps memory proportional to the file.
    records_ += static_cast<std::int64_t>(pending_.size());
    const std::int64_t uav_epochs = static_cast<std::int64_t>(log_.epochs.size() + 1) * log_.num_uavs;
    if (pending_.empty() || records_ < uav_epochs) {
      log_.integrity_error = "EPOCH_END mark of epoch " + std::to_string(log_.epochs.size()) + ": " +
                             std::to_string(pending_.size()) + " records for " + std::to_string(log_.num_uavs) +
                             " UAVs (" + std::to_string(records_) + " records for " + std::to_string(uav_epochs) +
                             " UAV-epochs so far)";
      log_.objects_after_last_mark = static_cast<std::int64_t>(pending_.size()) + 1;
      return;
    }
    std::vector<LoggedUavEpoch> row(log_.num_uavs);
    for (const Pending& p : pending_) {
      const auto* obs = dynamic_cast<const CObservation*>(p.object.get());
      const auto label = obs ? parse_uav_label(obs->sensorLabel) : std::nullopt;
      if (!label || !label->stream || label->uav >= log_.num_uavs) {
        count(log_.skipped, p.class_name, obs ? obs->sensorLabel : "");
        continue;
      }
      if (!apply_ours(row[label->uav], *label->stream, *obs)) {
        count(log_.skipped, p.class_name, obs->sensorLabel);
        continue;
      }
      if (*label->stream != UavStream::kMove) row[label->uav].reported = true;  // MOVE: the next iteration
      count(log_.used, p.class_name, to_string(*label->stream));
    }
    log_.epochs.push_back(std::move(row));
    log_.modes.push_back(modes);
  }

  void commit_final(int epoch) {
    if (epoch < 0) return;
    Eigen::Matrix3Xd q(3, log_.num_uavs);
    int seen = 0;
    for (const Pending& p : pending_) {
      const auto* o = dynamic_cast<const mrpt::obs::CObservationRobotPose*>(p.object.get());
      const auto label = o ? parse_uav_label(o->sensorLabel) : std::nullopt;
      if (!label || label->stream != UavStream::kTruth || label->uav >= log_.num_uavs) continue;
      q.col(label->uav) = belief_of(*o).mean_m;
      ++seen;
      count(log_.used, p.class_name, "TRUTH");
    }
    if (seen == log_.num_uavs) {
      log_.final_truth_epoch = epoch;
      log_.final_truth_m = q;
    }
  }

  // Returns false when the object's class does not fit its stream.
  bool apply_ours(LoggedUavEpoch& e, UavStream stream, const CObservation& obs) {
    const auto* pose = dynamic_cast<const mrpt::obs::CObservationRobotPose*>(&obs);
    const auto* daq = dynamic_cast<const mrpt::obs::CObservationRawDAQ*>(&obs);
    const int nt = log_.config->placement.scenario.num_bs_antennas();
    switch (stream) {
      case UavStream::kTruth:
        if (!pose) return false;
        e.truth_m = belief_of(*pose).mean_m;
        return true;
      case UavStream::kDr:
        if (!pose) return false;
        e.displacement_m = belief_of(*pose).mean_m;
        return true;
      case UavStream::kBelief:
        if (!pose) return false;
        e.filter_belief = belief_of(*pose);
        return true;
      case UavStream::kRefined:
        if (!pose) return false;
        e.refined_belief = belief_of(*pose);
        return true;
      case UavStream::kBeacon:
        if (!e.beacon_exact) return apply_bearing(e, obs);
        return true;
      case UavStream::kBeacon64:
        if (!daq || daq->AIN_double.size() != 3 || !all_finite(daq->AIN_double)) return false;
        e.beacon = localization::BeaconMeasurement{daq->AIN_double[0], daq->AIN_double[1], daq->AIN_double[2]};
        e.beacon_exact = true;
        return true;
      case UavStream::kCsi: {
        // Nt is known from the config: a row of any other length is refused.
        if (!daq || daq->AIN_double.size() != static_cast<std::size_t>(2 * nt) || !all_finite(daq->AIN_double))
          return false;
        fusion::CsiMeasurement c;
        c.y.resize(nt);
        for (int k = 0; k < nt; ++k) c.y(k) = {daq->AIN_double[2 * k], daq->AIN_double[2 * k + 1]};
        e.csi = std::move(c);
        return true;
      }
      case UavStream::kMove:
        return daq && daq->AIN_double.size() == 8;  // kept in the file; replay does not need it
      // The standard-type copies of DR and BEACON64 (version 2), for stock MRPT apps: checked
      // for their class, not used (the replay takes the double-precision records).
      case UavStream::kOdometry:
        return log_.format_version >= 2 && dynamic_cast<const mrpt::obs::CObservationOdometry*>(&obs) != nullptr;
      case UavStream::kBsRanges:
        return log_.format_version >= 2 && dynamic_cast<const mrpt::obs::CObservationBeaconRanges*>(&obs) != nullptr;
    }
    return false;
  }

  static bool apply_bearing(LoggedUavEpoch& e, const CObservation& obs) {
    const auto* b = dynamic_cast<const mrpt::obs::CObservationBearingRange*>(&obs);
    if (!b || b->sensedData.empty()) return false;
    const auto& z = b->sensedData.front();
    if (!std::isfinite(z.range) || !std::isfinite(z.yaw) || !std::isfinite(z.pitch)) return false;
    e.beacon = localization::BeaconMeasurement{z.range, z.yaw, -static_cast<double>(z.pitch)};
    e.beacon_exact = false;
    return true;
  }

  // ---- foreign logs ----
  LoggedUavEpoch& current(int uav) {
    if (uav >= static_cast<int>(foreign_epoch_.size())) foreign_epoch_.resize(uav + 1, 0);
    log_.num_uavs = std::max(log_.num_uavs, uav + 1);
    const int k = foreign_epoch_[uav];
    while (static_cast<int>(log_.epochs.size()) <= k) log_.epochs.emplace_back();
    // Rows stay ragged (a row grows only to the UAVs seen in it): memory follows the objects.
    if (static_cast<int>(log_.epochs[k].size()) <= uav) log_.epochs[k].resize(uav + 1);
    return log_.epochs[k][uav];
  }

  void open_epoch(int uav, const Eigen::Vector3d& d) {
    current(uav);
    if (foreign_epoch_[uav] + 1 >= kMaxEpochs) return;
    ++foreign_epoch_[uav];
    current(uav).displacement_m = d;
  }

  void add_foreign(const mrpt::serialization::CSerializable& obj, const std::string& class_name) {
    if (const auto* sf = dynamic_cast<const mrpt::obs::CSensoryFrame*>(&obj)) {
      for (const auto& o : *sf) {
        if (o) add_foreign(*o, o->GetRuntimeClass()->className);
      }
      return;
    }
    if (const auto* acts = dynamic_cast<const mrpt::obs::CActionCollection*>(&obj)) {
      for (std::size_t i = 0; i < acts->size(); ++i) {
        const mrpt::obs::CAction& a = acts->get(i);
        const std::string name = a.GetRuntimeClass()->className;
        if (const auto* m3 = dynamic_cast<const mrpt::obs::CActionRobotMovement3D*>(&a)) {
          const auto& p = m3->poseChange.mean;
          open_epoch(0, {p.x(), p.y(), p.z()});
          count(log_.used, name, "");
        } else if (const auto* m2 = dynamic_cast<const mrpt::obs::CActionRobotMovement2D*>(&a); m2 && m2->poseChange) {
          const auto p = m2->poseChange->getMeanVal();
          open_epoch(0, {p.x(), p.y(), 0.0});
          count(log_.used, name, "");
        } else {
          count(log_.skipped, name, "");
        }
      }
      return;
    }
    const auto* obs = dynamic_cast<const CObservation*>(&obj);
    const std::string label = obs ? obs->sensorLabel : "";
    const auto parsed = parse_uav_label(label);
    if (parsed && parsed->uav >= kMaxForeignUavs) {
      count(log_.skipped, class_name, label);
      return;
    }
    const int uav = parsed ? parsed->uav : 0;
    bool used = false;
    if (const auto* b = dynamic_cast<const mrpt::obs::CObservationBearingRange*>(&obj)) {
      used = apply_bearing(current(uav), *b);
    } else if (const auto* odo = dynamic_cast<const mrpt::obs::CObservationOdometry*>(&obj)) {
      if (uav >= static_cast<int>(last_odometry_.size())) last_odometry_.resize(uav + 1);
      const Eigen::Vector3d p(odo->odometry.x(), odo->odometry.y(), 0.0);
      if (last_odometry_[uav])
        open_epoch(uav, p - *last_odometry_[uav]);
      else
        current(uav);
      last_odometry_[uav] = p;
      used = true;
    } else if (const auto* pose = dynamic_cast<const mrpt::obs::CObservationRobotPose*>(&obj)) {
      const Eigen::Vector3d p = belief_of(*pose).mean_m;
      if (parsed && parsed->stream == UavStream::kDr) {
        open_epoch(uav, p);
        used = true;
      } else if ((parsed && parsed->stream == UavStream::kTruth) || label == "GROUND_TRUTH") {
        current(uav).truth_m = p;
        used = true;
      }
    }
    count(used ? log_.used : log_.skipped, class_name, label);
  }

  static void count(std::map<std::string, std::int64_t>& m, const std::string& cls, const std::string& label) {
    ++m[label.empty() ? cls : cls + " " + label];
  }

  MissionLog& log_;
  std::uint64_t digest_ = common::kFnvOffset;
  std::vector<Pending> pending_;
  std::map<std::string, std::int64_t> labels_seen_;  // ours, for END_OF_LOG's counts
  std::int64_t records_ = 0;                         // ours: records in the epochs committed (and the one at hand)
  std::vector<int> foreign_epoch_;
  std::vector<std::optional<Eigen::Vector3d>> last_odometry_;
};

}  // namespace

std::string MissionLog::stop_description() const {
  std::ostringstream o;
  o << read_status.describe();
  if (!integrity_error.empty()) o << "; integrity: " << integrity_error;
  if (ours && !complete) {
    o << "; no END_OF_LOG: partial log, " << epochs.size() << " complete epochs used";
    if (objects_after_last_mark > 0)
      o << ", " << objects_after_last_mark << " objects after the last good mark not used";
  }
  return o.str();
}

MissionLog load_mission_log(rawlog_io::RawlogReader& reader) {
  MissionLog log;
  Builder builder(log);
  while (std::optional<rawlog_io::RawlogObject> o = reader.next()) builder.add(*o);
  builder.finish();
  log.read_status = reader.status();
  if (log.read_status.objects == 0) throw common::InputError("not a readable rawlog: " + log.read_status.describe());
  return log;
}

}  // namespace losmimo::rawlog
