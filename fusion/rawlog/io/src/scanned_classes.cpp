// The layouts the scanner walks, one row per class: what MRPT 2.5's writeToStream writes for
// each version listed (tests/rawlog/rawlog_scanner_test.cpp checks every row against MRPT's
// own serialization of that class).
#include "object_scanner.h"

#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/registerAllClasses.h>
#include <mrpt/poses/CPoint3D.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>

#include "object_bytes.h"

namespace losmimo::rawlog_io::detail {

const Calibration& calibration() {
  static const Calibration c = [] {
    mrpt::obs::registerAllClasses_mrpt_obs();
    Calibration k;
    k.pose3d = serialize(mrpt::poses::CPose3D());
    k.pose3d_pdf = serialize(mrpt::poses::CPose3DPDFGaussian());
    mrpt::obs::CObservationBearingRange b;
    b.validCovariances = true;
    const std::size_t n0 = serialize(b).size();
    b.sensedData.resize(1);
    b.sensedData[0].landmarkID = 0;
    b.sensedData[0].covariance.setZero();
    k.bearing_cov_bytes = serialize(b).size() - n0 - (3 * sizeof(float) + sizeof(std::int32_t));
    k.pose2d = serialize(mrpt::poses::CPose2D());
    k.point3d = serialize(mrpt::poses::CPoint3D());
    mrpt::obs::CObservationOdometry odo;
    odo.hasVelocities = false;
    const std::size_t without = serialize(odo).size();
    odo.hasVelocities = true;
    k.odometry_velocity_bytes = serialize(odo).size() - without;
    return k;
  }();
  return c;
}

namespace {

void comment(ObjectCursor& c, const Calibration&, int version) {
  c.string("comment text");
  c.skip(8);  // timestamp
  if (version >= 1) c.string("sensorLabel");
}

void raw_daq(ObjectCursor& c, const Calibration&, int) {
  c.string("sensorLabel");
  c.skip(8 + 8);  // timestamp, sample_rate
  c.vector(1, "AIN_8bits");
  c.vector(2, "AIN_16bits");
  c.vector(4, "AIN_32bits");
  c.vector(4, "AIN_float");
  c.vector(8, "AIN_double");
  c.skip(2 + 1);  // AIN_channel_count, AIN_interleaved
  c.vector(1, "AOUT_8bits");
  c.vector(2, "AOUT_16bits");
  c.vector(4, "AOUT_float");
  c.vector(8, "AOUT_double");
  c.vector(1, "DIN");
  c.vector(1, "DOUT");
  c.vector(4, "CNTRIN_32bits");
  c.vector(8, "CNTRIN_double");
}

void bearing_range(ObjectCursor& c, const Calibration& cal, int) {
  c.skip(4 * 4);  // min/max distance, fields of view
  c.nested(cal.pose3d, "CPose3D");
  c.skip(8);  // timestamp
  const bool valid_cov = c.u8() != 0;
  if (!valid_cov) c.skip(3 * 4);
  const std::size_t per = 3 * 4 + 4 + (valid_cov ? cal.bearing_cov_bytes : 0);
  c.skip(c.count(per, "sensedData") * per);
  c.string("sensorLabel");
}

void beacon_ranges(ObjectCursor& c, const Calibration& cal, int) {
  c.skip(3 * 4);                                       // min/max distance, stdError
  const std::size_t per = cal.point3d.size() + 4 + 4;  // sensorLocationOnRobot, range, ID
  const std::uint32_t n = c.count(per, "sensedData");
  for (std::uint32_t i = 0; i < n; ++i) {
    c.nested(cal.point3d, "CPoint3D");
    c.skip(4 + 4);
  }
  c.nested(cal.pose2d, "CPose2D");  // auxEstimatePose
  c.string("sensorLabel");
  c.skip(8);  // timestamp
}

void odometry(ObjectCursor& c, const Calibration& cal, int) {
  c.nested(cal.pose2d, "CPose2D");
  c.string("sensorLabel");
  c.skip(8);                                             // timestamp
  if (c.u8() != 0) c.skip(2 * 4);                        // encoder ticks
  if (c.u8() != 0) c.skip(cal.odometry_velocity_bytes);  // velocityLocal
}

void robot_pose(ObjectCursor& c, const Calibration& cal, int) {
  c.nested(cal.pose3d_pdf, "CPose3DPDFGaussian");
  c.string("sensorLabel");
  c.skip(8);  // timestamp
  c.nested(cal.pose3d, "CPose3D");
}

}  // namespace

const std::vector<ScannedClass>& scanned_classes() {
  static const std::vector<ScannedClass> table = {
      {"CObservationComment", 0, 1, comment},
      {"CObservationRawDAQ", 0, 0, raw_daq},
      {"CObservationBearingRange", 3, 3, bearing_range},
      {"CObservationBeaconRanges", 3, 3, beacon_ranges},
      {"CObservationOdometry", 2, 2, odometry},
      {"CObservationRobotPose", 1, 1, robot_pose},
  };
  return table;
}

const ScannedClass* find_scanned_class(const std::string& name_without_namespace, int version) {
  for (const ScannedClass& row : scanned_classes()) {
    if (name_without_namespace == row.name && version >= row.min_version && version <= row.max_version) return &row;
  }
  return nullptr;
}

}  // namespace losmimo::rawlog_io::detail

namespace losmimo::rawlog_io {

std::vector<ScannedClassInfo> scanned_class_table() {
  std::vector<ScannedClassInfo> out;
  for (const detail::ScannedClass& row : detail::scanned_classes())
    out.push_back({std::string("mrpt::obs::") + row.name, row.min_version, row.max_version});
  return out;
}

}  // namespace losmimo::rawlog_io
