// libFuzzer target: the rawlog reader.
//
// Input: rawlog bytes, gzip or plain (the reader takes both), as `losmimo-replay --strict FILE`
// reads them: the bounded object-by-object RawlogReader in strict mode (every object's lengths
// are checked before MRPT parses it; classes it cannot bound stop the read), then
// load_mission_log, which interprets the objects (CONFIG, per-UAV streams, integrity marks).
// Properties (a violation traps, so libFuzzer reports it as a crash):
//   - reading never throws and always ends with a reason (end, truncated, corrupt, limit) and
//     the count of objects it returned; no object is larger than the limit;
//   - load_mission_log throws InputError or returns a log; any other exception aborts.
// Memory: the reader's limits bound every allocation; libFuzzer's -rss_limit_mb (2 GB) and
// -malloc_limit_mb catch anything that escapes them.

#include <cstddef>
#include <cstdint>
#include <string>

#include "losmimo/rawlog/log.h"
#include "losmimo/rawlog/reader.h"
#include "losmimo/common/input_error.h"

namespace lf = losmimo::rawlog;

namespace {
void require(bool ok) {
  if (!ok) __builtin_trap();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  lf::RawlogReaderOptions strict;
  strict.parse_unscanned_classes = false;

  const lf::RawlogContents contents = lf::read_rawlog_bytes(bytes, strict);
  require(contents.status.stop != lf::RawlogStop::kNone);
  require(contents.status.objects == static_cast<std::int64_t>(contents.objects.size()));
  require(!contents.status.describe().empty());
  for (const lf::RawlogObject& o : contents.objects) {
    require(o.object != nullptr && !o.class_name.empty());
    require(o.bytes.size() <= strict.max_object_bytes);
  }

  try {
    lf::RawlogReader reader = lf::RawlogReader::from_bytes(bytes, strict);
    const lf::MissionLog log = lf::load_mission_log(reader);
    require(log.read_status.stop != lf::RawlogStop::kNone);
    (void)log.stop_description();
  } catch (const losmimo::common::InputError&) {
  }
  return 0;
}
