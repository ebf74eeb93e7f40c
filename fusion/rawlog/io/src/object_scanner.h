#pragma once
// The scanner's view of one serialized MRPT object: a cursor that checks every length against
// the reader's limits before it steps over the bytes, and the table of the classes whose
// layout it knows (scanned_classes.cpp). A class the table holds is bounded before MRPT parses
// it; any other class is MRPT's to parse (in the sandbox for foreign logs). Private to
// rawlog_io.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "losmimo/fusion/rawlog/io/reader.h"

namespace losmimo::rawlog_io::detail {

inline constexpr std::uint8_t kEndFlag = 0x88;  // CArchive's end-of-object byte

// Why reading stopped, thrown inside the reader and turned into its status.
struct Stop {
  RawlogStop kind;
  std::string reason;
};

// The bytes of the object being read, from its first byte on: ensure(k) buffers at least k of
// them (false when the input ends first); data() is valid until the next ensure.
class ObjectWindow {
 public:
  virtual bool ensure(std::size_t k) = 0;
  virtual const std::uint8_t* data() const = 0;

 protected:
  ~ObjectWindow() = default;
};

class ObjectCursor {
 public:
  ObjectCursor(ObjectWindow& window, const RawlogReaderOptions& options) : w_(window), options_(options) {}

  std::size_t pos() const { return pos_; }
  void need(std::size_t n) {
    if (n > options_.max_object_bytes || pos_ + n > options_.max_object_bytes)
      throw Stop{RawlogStop::kLimit,
                 "object larger than max_object_bytes (" + std::to_string(options_.max_object_bytes) + ")"};
    if (!w_.ensure(pos_ + n)) throw Stop{RawlogStop::kTruncated, "data ends inside an object"};
  }
  const std::uint8_t* at() const { return w_.data() + pos_; }
  void skip(std::size_t n) {
    need(n);
    pos_ += n;
  }
  std::uint8_t u8() {
    need(1);
    return w_.data()[pos_++];
  }
  std::uint32_t u32() {
    need(4);
    std::uint32_t v;
    std::memcpy(&v, at(), 4);
    pos_ += 4;
    return v;
  }
  // A length-prefixed string, at most max_string_bytes long.
  void string(const char* what) {
    const std::uint32_t n = u32();
    if (n > options_.max_string_bytes)
      throw Stop{RawlogStop::kLimit, std::string(what) + " length " + std::to_string(n) + " above max_string_bytes"};
    skip(n);
  }
  // A length-prefixed array of `elem_bytes`-sized elements, at most max_object_bytes in all.
  void vector(std::size_t elem_bytes, const char* what) { skip(count(elem_bytes, what) * elem_bytes); }
  // A length prefix whose elements take `elem_bytes` each, checked against max_object_bytes.
  std::uint32_t count(std::size_t elem_bytes, const char* what) {
    const std::uint32_t n = u32();
    if (static_cast<std::uint64_t>(n) * elem_bytes > options_.max_object_bytes)
      throw Stop{RawlogStop::kLimit, std::string(what) + " length " + std::to_string(n) + " above max_object_bytes"};
    return n;
  }
  // A nested fixed-size object: its header must match the calibrated one exactly.
  void nested(const std::vector<std::uint8_t>& model, const char* what) {
    const std::size_t header = 1 + (model[0] & 0x7F) + 1;
    need(header);
    if (std::memcmp(at(), model.data(), header) != 0)
      throw Stop{RawlogStop::kCorrupt, std::string("nested ") + what + " header mismatch"};
    skip(model.size());
  }

 private:
  ObjectWindow& w_;
  const RawlogReaderOptions& options_;
  std::size_t pos_ = 0;
};

// Serialized sizes of the fixed-size nested objects, measured from MRPT itself at start-up.
struct Calibration {
  std::vector<std::uint8_t> pose3d, pose3d_pdf, pose2d, point3d;  // whole envelopes of default objects
  std::size_t bearing_cov_bytes = 0;                              // one TMeasurement::covariance
  std::size_t odometry_velocity_bytes = 0;                        // CObservationOdometry::velocityLocal
};
const Calibration& calibration();

// One row per class the scanner bounds: its name without "mrpt::obs::", the serialization
// versions whose layout `scan` walks (the cursor stands after the version byte; scan steps to
// just before the end-of-object flag).
struct ScannedClass {
  const char* name;
  int min_version, max_version;
  void (*scan)(ObjectCursor& c, const Calibration& cal, int version);
};
const std::vector<ScannedClass>& scanned_classes();
// The row for this class and version, or nullptr.
const ScannedClass* find_scanned_class(const std::string& name_without_namespace, int version);

}  // namespace losmimo::rawlog_io::detail
