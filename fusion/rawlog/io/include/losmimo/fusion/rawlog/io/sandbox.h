#pragma once
// MRPT objects of rawlogs losmimo did not write, parsed in a bounded child process.
//
// MRPT's deserializers trust the file: a corrupted field can crash them (a null CPosePDF in
// CActionRobotMovement2D, an aligned allocator that returns null instead of throwing) or make
// them allocate gigabytes. So the reader (reader.h) hands foreign objects to an ObjectSandbox:
// a child process forked from this one that reads the log itself, with the same reader, under
// limits (address space and data segment SandboxLimits::memory_bytes above its size at the
// fork, CPU seconds per log, no core dumps). For each object it parsed, the child sends back
// (index, uncompressed byte offset, class, the object re-serialized by MRPT), after checking
// that MRPT reads those bytes back (so parsing them here does only what already succeeded
// there, within the child's limits); then the final status. A crash, a memory or CPU limit, or
// no progress for stall_seconds ends the child: the reader stops with a status naming the
// object index, byte offset and class the child was parsing. The objects before it are kept.
//
// One child serves one log at a time and is reused for the next log (the fuzzer runs many);
// after a death the next log forks a new one. Forking needs a single-threaded process, as the
// replay is while it reads.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace losmimo::rawlog_io {

struct RawlogObject;
struct RawlogReadStatus;
struct RawlogReaderOptions;

struct SandboxLimits {
  std::size_t memory_bytes = std::size_t{512} << 20;  // address space / data above the child's size at fork
  int cpu_seconds = 60;                               // per log
  int stall_seconds = 30;                             // wall time without an object: killed
};

// What the child reads: the rawlog file at `path`, or `bytes`, from uncompressed byte `offset`
// on, numbering objects from `index`.
struct SandboxJob {
  bool from_file = true;
  std::string path;
  std::string bytes;
  std::uint64_t offset = 0;
  std::int64_t index = 0;
};

// The child's side of a job, for the reader (reader.cpp runs the job with it).
class SandboxChannel {
 public:
  virtual ~SandboxChannel() = default;
  // Before MRPT parses the object: what a crash will be reported as.
  virtual void parsing(std::int64_t index, std::uint64_t offset, const std::string& class_name) = 0;
  // Re-serializes and sends the object; false (and `why`) if it cannot (too large, or MRPT cannot
  // read its own bytes back): the job stops there.
  virtual bool send(const RawlogObject& object, std::uint64_t end_offset, std::string& why) = 0;
};
// Reads the job's objects with the in-process reader (reader.cpp); returns the final status.
RawlogReadStatus run_sandbox_job(const SandboxJob& job, const RawlogReaderOptions& options, SandboxChannel& channel);

class ObjectSandbox {
 public:
  explicit ObjectSandbox(const SandboxLimits& limits);
  ~ObjectSandbox();  // ends the child
  ObjectSandbox(const ObjectSandbox&) = delete;
  ObjectSandbox& operator=(const ObjectSandbox&) = delete;

  // Starts a job (forking a child if there is none); then next() until nullopt, then status().
  void start(const SandboxJob& job, const RawlogReaderOptions& options);
  std::optional<RawlogObject> next();
  const RawlogReadStatus& status() const;
  // The child is alive and between jobs: the sandbox can be reused.
  bool reusable() const;
  const SandboxLimits& limits() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// A sandbox from a process-wide pool (created on first use) and its return: a reader takes one
// per foreign log, so a fuzzer or a test suite forks once, not once per log.
std::unique_ptr<ObjectSandbox> acquire_sandbox(const SandboxLimits& limits);
void release_sandbox(std::unique_ptr<ObjectSandbox> sandbox);

}  // namespace losmimo::rawlog_io
