#pragma once
// Reads an MRPT rawlog object by object, never trusting a length it has not checked.
//
// MRPT objects carry no length prefix, and MRPT's deserializers resize vectors and strings to a
// length field before reading them (a corrupted field costs gigabytes), or crash on some
// corrupted fields. So:
//   - losmimo's own logs (object 0 is the CONFIG comment, kRawlogMagic) are read in this process:
//     before MRPT parses an object, a scanner walks its bytes with the known layout of the
//     classes losmimo writes (scanned_class_table(): one row per class and version; nested
//     CPose3D / CPose3DPDFGaussian / CPose2D / CPoint3D are fixed-size and calibrated at
//     start-up from MRPT itself), checks every length against the limits below, and buffers the
//     whole object; MRPT then parses exactly those bytes from memory. Any other class in such a
//     log stops the read (limit): losmimo never writes one.
//   - other logs ("foreign") are parsed in a bounded child process (sandbox.h, the default
//     ForeignObjects::kSandbox), which returns each object it could parse with its index and
//     offset; a crash or a memory or CPU limit there stops the read with a status naming the
//     object index, byte offset and class. kStop instead stops at the first object the scanner
//     cannot bound (strict mode); kInProcess lets MRPT parse it here, unbounded (only the
//     sandbox's child does that).
//
// Input: a gzip file (what MRPT writes) or an uncompressed one (zlib reads both), or bytes in
// memory, at most max_total_bytes uncompressed. A truncated or corrupt input never throws from
// next(): reading stops, and status() says where (object index, uncompressed byte offset) and
// why.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "losmimo/fusion/rawlog/io/sandbox.h"

namespace mrpt::serialization {
class CSerializable;
}

namespace losmimo::rawlog_io {

// A log is losmimo's own when object 0 is a CObservationComment whose text starts with this
// magic and a space (the CONFIG comment, rawlog/format.h).
inline constexpr const char* kRawlogMagic = "losmimo-rawlog";

enum class ForeignObjects { kSandbox, kStop, kInProcess };

struct RawlogReaderOptions {
  std::size_t max_object_bytes = std::size_t{64} << 20;  // one object, serialized
  std::size_t max_string_bytes = std::size_t{1} << 20;   // a label or comment text
  // The whole log, uncompressed (the largest shipped with MRPT: 5.9 MB; losmimo's 256-UAV,
  // 256-antenna test mission: 32 MB).
  std::uint64_t max_total_bytes = std::uint64_t{256} << 20;
  ForeignObjects foreign = ForeignObjects::kSandbox;
  SandboxLimits sandbox;
};

struct RawlogObject {
  std::int64_t index = 0;    // 0-based position in the file
  std::uint64_t offset = 0;  // uncompressed byte offset of its first byte
  std::string class_name;
  std::shared_ptr<mrpt::serialization::CSerializable> object;
  // As serialized in the file (for the integrity digests); objects from the sandbox: as MRPT
  // re-serialized them.
  std::vector<std::uint8_t> bytes;
};

enum class RawlogStop {
  kNone,       // still reading
  kEnd,        // clean end of file at an object boundary
  kTruncated,  // the data ends inside an object, or the gzip stream ends early
  kCorrupt,    // bad bytes: failed a check, MRPT refused it, or gzip data error
  kLimit,      // a length above the limits, or a class strict mode does not parse
};
std::string to_string(RawlogStop stop);

struct RawlogReadStatus {
  RawlogStop stop = RawlogStop::kNone;
  std::int64_t objects = 0;  // objects returned
  std::uint64_t offset = 0;  // uncompressed offset where reading stopped
  std::string reason;        // empty for kEnd
  // "stopped at object 12 (byte 3456): truncated: ..." (or "complete: 12 objects").
  std::string describe() const;
};

class RawlogReader {
 public:
  // Throws std::runtime_error("<path>: cannot open ...") if the file cannot be opened.
  static RawlogReader open_file(const std::string& path, const RawlogReaderOptions& options = {});
  static RawlogReader from_bytes(std::string bytes, const RawlogReaderOptions& options = {});

  RawlogReader(RawlogReader&&) noexcept;
  RawlogReader& operator=(RawlogReader&&) noexcept;
  ~RawlogReader();

  // The next object, or nullopt when reading stopped (then status() says why).
  std::optional<RawlogObject> next();
  const RawlogReadStatus& status() const;

  struct Impl;

 private:
  explicit RawlogReader(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// The classes whose layout the scanner knows, with the serialization versions it walks
// (inclusive): what a losmimo rawlog may hold, and what strict mode (ForeignObjects::kStop)
// reads from any log.
struct ScannedClassInfo {
  std::string name;  // with its namespace, as MRPT 2 writes it: "mrpt::obs::CObservationComment"
  int min_version = 0;
  int max_version = 0;
};
std::vector<ScannedClassInfo> scanned_class_table();

// Reads everything (for tests and the fuzz target): the objects and the final status. Never
// throws on any input; with ForeignObjects::kSandbox or kStop no allocation in this process
// exceeds the limits.
struct RawlogContents {
  std::vector<RawlogObject> objects;
  RawlogReadStatus status;
};
RawlogContents read_rawlog_bytes(std::string bytes, const RawlogReaderOptions& options = {});

}  // namespace losmimo::rawlog_io
