#pragma once
// The walk through an MRPT rawlog that the range-only and the bearing-range loaders share: both
// log formats (a sensory frame after its action collection, or bare observations), odometry
// chained from the actions (or from CObservationOdometry poses) up to the next frame, and every
// object counted as used or skipped by class name.
//
// Derived (CRTP) supplies, with Increment the type of Frame::odometry:
//   void add_observation_to(const CObservation&, Frame&);    one observation of a frame
//   void add_action(const CAction&);                         add_increment, or a skip counted
//   Increment odometry_increment(const Eigen::Vector4d& u);  u = (dx, dy, 0, dphi) between two
//                                                            CObservationOdometry poses
//   static Increment chain(const Increment&, const Increment&);  u1 (+) u2 with its covariance
// Observation is the class that forms a frame by itself when it is not inside a sensory frame.

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include <Eigen/Core>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/system/datetime.h>

#include "losmimo/localization/pose/odometry_model.h"
#include "losmimo/fusion/rawlog/io/reader.h"

namespace losmimo::mrpt_logs::detail {

// MRPT time as seconds since the Unix epoch; nan for INVALID_TIMESTAMP.
inline double seconds_of(const mrpt::Clock::time_point& t) {
  return t == INVALID_TIMESTAMP ? std::numeric_limits<double>::quiet_NaN() : mrpt::Clock::toDouble(t);
}

template <class Derived, class Log, class Frame, class Observation>
class LogLoader {
 public:
  using Increment = decltype(Frame::odometry);

  explicit LogLoader(Log& log) : log_(log) {}

  void add(const mrpt::serialization::CSerializable& obj, const std::string& class_name) {
    if (const auto* sf = dynamic_cast<const mrpt::obs::CSensoryFrame*>(&obj)) {
      Frame frame;
      frame.step = sensory_frames_++;
      frame.timestamp_s = std::numeric_limits<double>::quiet_NaN();
      for (const auto& o : *sf) {
        if (!o) continue;
        if (std::isnan(frame.timestamp_s)) frame.timestamp_s = seconds_of(o->timestamp);
        derived().add_observation_to(*o, frame);
      }
      push_frame(std::move(frame));
      return;
    }
    if (const auto* acts = dynamic_cast<const mrpt::obs::CActionCollection*>(&obj)) {
      for (std::size_t i = 0; i < acts->size(); ++i) derived().add_action(acts->get(i));
      return;
    }
    const std::int64_t index = top_level_++;
    if (const auto* b = dynamic_cast<const Observation*>(&obj)) {
      Frame frame;
      frame.step = index;
      frame.timestamp_s = seconds_of(b->timestamp);
      derived().add_observation_to(*b, frame);
      push_frame(std::move(frame));
      return;
    }
    if (const auto* odo = dynamic_cast<const mrpt::obs::CObservationOdometry*>(&obj)) {
      const Eigen::Vector4d p(odo->odometry.x(), odo->odometry.y(), 0.0, odo->odometry.phi());
      if (last_odometry_)
        add_increment(derived().odometry_increment(localization::increment_between(*last_odometry_, p)));
      last_odometry_ = p;
      ++log_.used[class_name];
      return;
    }
    ++log_.skipped[class_name];
  }

  void finish() {
    if (pending_) ++log_.trailing_actions;
  }

 protected:
  void add_increment(const Increment& u) { pending_ = pending_ ? Derived::chain(*pending_, u) : u; }

  Log& log_;

 private:
  Derived& derived() { return static_cast<Derived&>(*this); }

  void push_frame(Frame frame) {
    if (pending_) {
      frame.has_odometry = true;
      frame.odometry = *pending_;
    }
    pending_.reset();
    log_.frames.push_back(std::move(frame));
  }

  std::int64_t sensory_frames_ = 0;
  std::int64_t top_level_ = 0;
  std::optional<Increment> pending_;
  std::optional<Eigen::Vector4d> last_odometry_;
};

// Every object of the reader through a Loader (LogLoader's derived class) into a fresh Log.
template <class Loader, class Log>
Log load_log(rawlog_io::RawlogReader& reader) {
  Log log;
  Loader loader(log);
  while (auto object = reader.next()) {
    if (object->object) loader.add(*object->object, object->class_name);
  }
  loader.finish();
  log.read_status = reader.status();
  return log;
}

}  // namespace losmimo::mrpt_logs::detail
