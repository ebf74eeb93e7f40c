// libFuzzer target: the rawlog reader, as `losmimo-replay` reads logs.
//
// Input: rawlog bytes, gzip or plain (the reader takes both). Read in two ways:
//   1. strict (`--strict`: ForeignObjects::kStop): every object's lengths are checked before
//      MRPT parses it in this process; classes the scanner cannot bound stop the read;
//   2. as the replay reads by default (ForeignObjects::kSandbox): losmimo's own logs in this
//      process, foreign logs through the sandbox's child process (rawlog_io/sandbox.h), which may crash,
//      run out of its memory or CPU limit: this process must not.
// then load_mission_log, which interprets the objects (CONFIG, per-UAV streams, integrity marks,
// foreign observations and actions).
// Properties (a violation traps, so libFuzzer reports it as a crash):
//   - reading never throws and always ends with a reason (end, truncated, corrupt, limit) and
//     the count of objects it returned; no object is larger than the limit;
//   - the sandboxed read returns objects in index order with increasing offsets;
//   - load_mission_log throws InputError or returns a log; any other exception aborts.
// Memory: the reader's limits bound every allocation in this process; libFuzzer's
// -rss_limit_mb (2 GB) and -malloc_limit_mb catch anything that escapes them. The sandbox's
// child is bounded by its own limits and is not this process.
// The MRPT datasets (mrpt-common, /usr/share/mrpt/datasets) seed the campaign by hand
// (docs/reliability.md); tests/fuzz/corpus/fuzz_rawlog holds the kept corpus.

#include <cstddef>
#include <cstdint>
#include <string>

#include "losmimo/placement/common/input_error.h"
#include "losmimo/fusion/rawlog/mission/log.h"
#include "losmimo/fusion/rawlog/io/reader.h"

namespace lr = losmimo::rawlog;
namespace io = losmimo::rawlog_io;

namespace {
void require(bool ok) {
  if (!ok) __builtin_trap();
}

void check_contents(const io::RawlogContents& contents, const io::RawlogReaderOptions& options) {
  require(contents.status.stop != io::RawlogStop::kNone);
  require(contents.status.objects == static_cast<std::int64_t>(contents.objects.size()));
  require(!contents.status.describe().empty());
  std::int64_t index = 0;
  std::uint64_t offset = 0;
  for (const io::RawlogObject& o : contents.objects) {
    require(o.object != nullptr && !o.class_name.empty());
    require(o.bytes.size() <= options.max_object_bytes);
    require(o.index == index++);
    require(o.index == 0 || o.offset > offset);
    offset = o.offset;
  }
}

void interpret(const std::string& bytes, const io::RawlogReaderOptions& options) {
  try {
    io::RawlogReader reader = io::RawlogReader::from_bytes(bytes, options);
    const lr::MissionLog log = lr::load_mission_log(reader);
    require(log.read_status.stop != io::RawlogStop::kNone);
    (void)log.stop_description();
  } catch (const losmimo::common::InputError&) {}
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  io::RawlogReaderOptions strict;
  strict.foreign = io::ForeignObjects::kStop;
  interpret(bytes, strict);

  io::RawlogReaderOptions sandboxed;  // the default: foreign objects in the sandbox
  // Inputs are small (-max_len): a child that needs more than 64 MiB or 2 s is stopped, which is
  // what the limits are for; larger budgets only make those inputs slow.
  sandboxed.sandbox.memory_bytes = std::size_t{64} << 20;
  sandboxed.sandbox.cpu_seconds = 2;
  sandboxed.sandbox.stall_seconds = 20;
  // One sandboxed pass per input (each costs the child's parse and this process's re-parse):
  // the objects and their order, or the interpretation, by the input's length.
  if (size % 2 == 0) {
    check_contents(io::read_rawlog_bytes(bytes, sandboxed), sandboxed);
  } else {
    interpret(bytes, sandboxed);
  }
  return 0;
}
