// The scanner's class table (fusion/rawlog/io/src/scanned_classes.cpp) against MRPT's own
// serialization: every row's class, default-constructed from MRPT's class registry and filled
// with variable-length content, is bounded to exactly the bytes MRPT writes for it, in the
// version MRPT writes; a registered class outside the table is left to MRPT (strict mode stops).
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <string>

#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRawDAQ.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/registerAllClasses.h>
#include <mrpt/rtti/CObject.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/serialization/CSerializable.h>

#include "losmimo/fusion/rawlog/io/reader.h"

namespace losmimo::rawlog_io {
namespace {

std::string bytes_of(const mrpt::serialization::CSerializable& o) {
  mrpt::io::CMemoryStream mem;
  auto a = mrpt::serialization::archiveFrom(mem);
  a << o;
  return {static_cast<const char*>(mem.getRawBufferData()), static_cast<std::size_t>(mem.getTotalBytesCount())};
}

// The serialization version byte MRPT wrote (after the 0x80|length byte and the class name).
int written_version(const std::string& bytes) {
  const std::size_t name_len = static_cast<unsigned char>(bytes.at(0)) & 0x7F;
  return static_cast<unsigned char>(bytes.at(1 + name_len));
}

// Content that makes each table class's variable-length fields non-empty, so that a wrong
// element size or a missed field in a row changes the length the scanner finds.
void fill(mrpt::serialization::CSerializable& o) {
  if (auto* c = dynamic_cast<mrpt::obs::CObservationComment*>(&o)) {
    c->text = "a comment\nof two lines";
  } else if (auto* d = dynamic_cast<mrpt::obs::CObservationRawDAQ*>(&o)) {
    d->AIN_double = {1.0, 2.0, 3.0};
    d->AIN_16bits = {7, 8};
    d->CNTRIN_32bits = {9};
    d->DOUT = {1, 0, 1};
  } else if (auto* b = dynamic_cast<mrpt::obs::CObservationBearingRange*>(&o)) {
    b->validCovariances = true;
    b->sensedData.resize(3);
    for (std::size_t i = 0; i < b->sensedData.size(); ++i) {
      b->sensedData[i].landmarkID = static_cast<int32_t>(i);  // MRPT refuses duplicate IDs
      b->sensedData[i].covariance.setIdentity();
    }
  } else if (auto* r = dynamic_cast<mrpt::obs::CObservationBeaconRanges*>(&o)) {
    r->sensedData.resize(4);
    for (std::size_t i = 0; i < r->sensedData.size(); ++i) r->sensedData[i].beaconID = static_cast<int32_t>(i);
  } else if (auto* odo = dynamic_cast<mrpt::obs::CObservationOdometry*>(&o)) {
    odo->hasEncodersInfo = true;
    odo->hasVelocities = true;
  }
  if (auto* obs = dynamic_cast<mrpt::obs::CObservation*>(&o)) obs->sensorLabel = "UAV3_BEACON";
}

std::shared_ptr<mrpt::serialization::CSerializable> make(const std::string& name) {
  mrpt::obs::registerAllClasses_mrpt_obs();
  const mrpt::rtti::CObject::Ptr p = mrpt::rtti::classFactory(name);
  return std::dynamic_pointer_cast<mrpt::serialization::CSerializable>(p);
}

void expect_bounded(const mrpt::serialization::CSerializable& o, const ScannedClassInfo& row, const char* what) {
  const std::string bytes = bytes_of(o);
  const int v = written_version(bytes);
  EXPECT_GE(v, row.min_version) << row.name << " (" << what << "): MRPT writes version " << v;
  EXPECT_LE(v, row.max_version) << row.name << " (" << what << "): MRPT writes version " << v;
  RawlogReaderOptions strict;
  strict.foreign = ForeignObjects::kStop;  // only what the scanner bounds is read
  const RawlogContents got = read_rawlog_bytes(bytes + bytes, strict);
  ASSERT_EQ(got.status.stop, RawlogStop::kEnd) << row.name << " (" << what << "): " << got.status.describe();
  ASSERT_EQ(got.objects.size(), 2u) << row.name;
  EXPECT_EQ(got.objects[0].bytes.size(), bytes.size()) << row.name << " (" << what << ")";
  EXPECT_EQ(got.objects[1].offset, bytes.size()) << row.name << " (" << what << ")";
  EXPECT_EQ(got.objects[0].class_name, row.name);
}

TEST(ScannedClasses, EveryRowIsARegisteredMrptClassBoundedToExactlyTheBytesMrptWrites) {
  const std::vector<ScannedClassInfo> table = scanned_class_table();
  ASSERT_GE(table.size(), 6u);
  for (const ScannedClassInfo& row : table) {
    const auto empty = make(row.name);
    ASSERT_TRUE(empty) << row.name << " is not a class MRPT's registry knows";
    expect_bounded(*empty, row, "default");
    const auto filled = make(row.name);
    fill(*filled);
    expect_bounded(*filled, row, "filled");
    EXPECT_GT(bytes_of(*filled).size(), bytes_of(*empty).size()) << row.name << ": fill() left it at its default size";
  }
}

TEST(ScannedClasses, AClassOutsideTheTableStopsStrictModeNamingIt) {
  for (const ScannedClassInfo& row : scanned_class_table()) ASSERT_NE(row.name, "mrpt::obs::CObservation2DRangeScan");
  mrpt::obs::CObservation2DRangeScan scan;
  scan.resizeScan(5);
  RawlogReaderOptions strict;
  strict.foreign = ForeignObjects::kStop;
  const RawlogContents got = read_rawlog_bytes(bytes_of(scan), strict);
  EXPECT_TRUE(got.objects.empty());
  EXPECT_EQ(got.status.stop, RawlogStop::kLimit);
  EXPECT_NE(got.status.reason.find("CObservation2DRangeScan"), std::string::npos) << got.status.reason;
  // In-process mode hands it to MRPT, which reads it whole.
  RawlogReaderOptions in_process;
  in_process.foreign = ForeignObjects::kInProcess;
  const RawlogContents whole = read_rawlog_bytes(bytes_of(scan), in_process);
  ASSERT_EQ(whole.objects.size(), 1u) << whole.status.describe();
  EXPECT_EQ(whole.status.stop, RawlogStop::kEnd);
}

}  // namespace
}  // namespace losmimo::rawlog_io
