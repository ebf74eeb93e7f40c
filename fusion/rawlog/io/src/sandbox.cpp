#include "losmimo/fusion/rawlog/io/sandbox.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "losmimo/placement/common/test_hook.h"
#include "losmimo/fusion/rawlog/io/reader.h"
#include "object_bytes.h"

// Sanitizer runtimes (ASan, libFuzzer) call a death callback on an error; the child must not
// run the parent's (libFuzzer's writes a crash file for the parent's input). Weak: absent in
// normal builds.
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

namespace losmimo::rawlog_io {

namespace {

constexpr std::uint8_t kMsgObject = 1;
constexpr std::uint8_t kMsgStatus = 2;
constexpr std::size_t kMaxClassName = 128;
constexpr std::size_t kMaxReason = 4096;

// Shared with the child (MAP_SHARED): the object it is parsing, for the report of its death.
struct Progress {
  std::atomic<std::int64_t> index{0};
  std::atomic<std::uint64_t> offset{0};
  std::atomic<std::uint32_t> class_len{0};
  char class_name[kMaxClassName];
};

bool write_all(int fd, const void* data, std::size_t n) {
  const auto* p = static_cast<const char*>(data);
  while (n > 0) {
    const ssize_t k = ::send(fd, p, n, MSG_NOSIGNAL);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    p += k;
    n -= static_cast<std::size_t>(k);
  }
  return true;
}

// Reads exactly n bytes (blocking); false at EOF or error.
bool read_all(int fd, void* data, std::size_t n) {
  auto* p = static_cast<char*>(data);
  while (n > 0) {
    const ssize_t k = ::read(fd, p, n);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    p += k;
    n -= static_cast<std::size_t>(k);
  }
  return true;
}

template <typename T>
void put(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}
void put_string(std::string& out, const std::string& s) {
  put<std::uint64_t>(out, s.size());
  out += s;
}

std::size_t status_kb(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key, 0) == 0) return std::stoul(line.substr(std::strlen(key)));
  }
  return 0;
}

// ---- the child ----

class ChildChannel : public SandboxChannel {
 public:
  ChildChannel(int fd, Progress* progress, std::size_t max_object_bytes)
      : fd_(fd), progress_(progress), max_object_bytes_(max_object_bytes) {}
  void parsing(std::int64_t index, std::uint64_t offset, const std::string& class_name) override {
    const std::size_t n = std::min(class_name.size(), kMaxClassName);
    std::memcpy(progress_->class_name, class_name.data(), n);
    progress_->class_len = static_cast<std::uint32_t>(n);
    progress_->offset = offset;
    progress_->index = index;
    common::test_pause_point("sandbox.parsing");
  }
  bool send(const RawlogObject& o, std::uint64_t end_offset, std::string& why) override {
    std::vector<std::uint8_t> bytes = serialize(*o.object);
    if (bytes.size() > max_object_bytes_) {
      why = o.class_name + ": re-serialized, " + std::to_string(bytes.size()) + " bytes: above max_object_bytes";
      return false;
    }
    try {
      deserialize(bytes);  // what the parent will do, done here first
    } catch (const std::exception& e) {
      why = o.class_name + ": MRPT cannot read back its own serialization of it: " + e.what();
      return false;
    }
    std::string msg;
    put<std::uint8_t>(msg, kMsgObject);
    put<std::int64_t>(msg, o.index);
    put<std::uint64_t>(msg, o.offset);
    put<std::uint64_t>(msg, end_offset);
    put_string(msg, o.class_name.substr(0, kMaxClassName));
    put_string(msg, std::string(bytes.begin(), bytes.end()));
    if (!write_all(fd_, msg.data(), msg.size())) ::_exit(0);  // the parent is gone
    return true;
  }

 private:
  int fd_;
  Progress* progress_;
  std::size_t max_object_bytes_;
};

void limit(int resource, rlim_t value) {
  rlimit r{};
  if (::getrlimit(resource, &r) != 0) return;
  if (r.rlim_max != RLIM_INFINITY && value > r.rlim_max) value = r.rlim_max;
  if (r.rlim_cur != RLIM_INFINITY && r.rlim_cur < value) return;  // already lower
  r.rlim_cur = value;
  ::setrlimit(resource, &r);
}

[[noreturn]] void child_main(int fd, Progress* progress, const SandboxLimits& limits, pid_t parent) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(0);
  if (__sanitizer_set_death_callback) __sanitizer_set_death_callback(nullptr);
  for (const int sig : {SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL, SIGXCPU, SIGTERM, SIGINT, SIGALRM})
    ::signal(sig, SIG_DFL);
  const int null = ::open("/dev/null", O_RDWR | O_CLOEXEC);
  if (null >= 0) {
    ::dup2(null, STDOUT_FILENO);
    ::dup2(null, STDERR_FILENO);
  }
  limit(RLIMIT_CORE, 0);
  // Memory: the child may grow by memory_bytes above what it has now (data segment and
  // address space; under AddressSanitizer only the data limit bites).
  limit(RLIMIT_DATA, static_cast<rlim_t>(status_kb("VmData:")) * 1024 + limits.memory_bytes);
  limit(RLIMIT_AS, static_cast<rlim_t>(status_kb("VmSize:")) * 1024 + limits.memory_bytes);
  while (true) {
    std::uint64_t n = 0;
    if (!read_all(fd, &n, sizeof n) || n > (std::uint64_t{1} << 32)) ::_exit(0);
    std::string raw(n, '\0');
    if (!read_all(fd, raw.data(), n)) ::_exit(0);
    std::size_t at = 0;
    const auto get = [&](auto& v) {
      std::memcpy(&v, raw.data() + at, sizeof v);
      at += sizeof v;
    };
    std::uint8_t from_file = 0;
    SandboxJob job;
    RawlogReaderOptions options;
    std::uint64_t max_object = 0, max_string = 0, max_total = 0;
    get(from_file);
    get(job.offset);
    get(job.index);
    get(max_object);
    get(max_string);
    get(max_total);
    job.from_file = from_file != 0;
    (job.from_file ? job.path : job.bytes) = raw.substr(at);
    options.max_object_bytes = max_object;
    options.max_string_bytes = max_string;
    options.max_total_bytes = max_total;
    options.foreign = ForeignObjects::kInProcess;
    // CPU: this log's budget on top of what the child has used so far.
    rusage used{};
    ::getrusage(RUSAGE_SELF, &used);
    rlimit cpu{};
    ::getrlimit(RLIMIT_CPU, &cpu);
    cpu.rlim_cur = static_cast<rlim_t>(used.ru_utime.tv_sec + used.ru_stime.tv_sec + 1 + limits.cpu_seconds);
    if (cpu.rlim_max != RLIM_INFINITY && cpu.rlim_cur > cpu.rlim_max) cpu.rlim_cur = cpu.rlim_max;
    ::setrlimit(RLIMIT_CPU, &cpu);

    ChildChannel channel(fd, progress, max_object);
    RawlogReadStatus s;
    try {
      s = run_sandbox_job(job, options, channel);
    } catch (const std::bad_alloc&) {
      s.stop = RawlogStop::kLimit;
      s.objects = progress->index;
      s.offset = progress->offset;
      s.reason = "out of memory in the sandbox";
    } catch (const std::exception& e) {
      s.stop = RawlogStop::kCorrupt;
      s.objects = progress->index;
      s.offset = progress->offset;
      s.reason = e.what();
    }
    if (s.stop == RawlogStop::kLimit && s.reason.find("out of memory") != std::string::npos) {
      s.reason += " (the sandbox allows " + std::to_string(limits.memory_bytes >> 20) + " MiB)";
    }
    std::string msg;
    put<std::uint8_t>(msg, kMsgStatus);
    put<std::uint8_t>(msg, static_cast<std::uint8_t>(s.stop));
    put<std::int64_t>(msg, s.objects);
    put<std::uint64_t>(msg, s.offset);
    put_string(msg, s.reason.substr(0, kMaxReason));
    if (!write_all(fd, msg.data(), msg.size())) ::_exit(0);
  }
}

}  // namespace

// ---- the parent ----

struct ObjectSandbox::Impl {
  SandboxLimits limits;
  Progress* progress = nullptr;
  pid_t pid = -1;
  int fd = -1;
  bool job_active = false;
  RawlogReadStatus status;
  static constexpr std::size_t kReceiveChunk = 256 * 1024;
  std::vector<char> rbuf;  // received, not yet taken
  std::size_t rpos = 0;

  ~Impl() {
    end_child();
    if (progress) ::munmap(progress, sizeof(Progress));
  }

  void end_child() {
    if (fd >= 0) ::close(fd);
    fd = -1;
    if (pid > 0) {
      ::kill(pid, SIGKILL);
      while (::waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {}
    }
    pid = -1;
    job_active = false;
    rbuf.clear();
    rpos = 0;
  }

  void fork_child() {
    if (!progress) {
      void* p = ::mmap(nullptr, sizeof(Progress), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
      if (p == MAP_FAILED) throw std::runtime_error(std::string("sandbox: mmap failed: ") + std::strerror(errno));
      progress = new (p) Progress();
    }
    int fds[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) {
      throw std::runtime_error(std::string("sandbox: socketpair failed: ") + std::strerror(errno));
    }
    const pid_t parent = ::getpid();
    const pid_t child = ::fork();
    if (child < 0) {
      ::close(fds[0]);
      ::close(fds[1]);
      throw std::runtime_error(std::string("sandbox: fork failed: ") + std::strerror(errno));
    }
    if (child == 0) {
      ::close(fds[0]);
      child_main(fds[1], progress, limits, parent);
    }
    ::close(fds[1]);
    fd = fds[0];
    pid = child;
  }

  // Reads n bytes from the child; false if it died or stalled (status then says why). Buffered:
  // the child runs ahead, and one wake-up here takes every object it has sent.
  bool receive(void* data, std::size_t n) {
    auto* p = static_cast<char*>(data);
    while (n > 0) {
      if (rpos == rbuf.size()) {
        rbuf.resize(kReceiveChunk);
        rpos = 0;
        pollfd pfd{fd, POLLIN, 0};
        const int r = ::poll(&pfd, 1, limits.stall_seconds * 1000);
        if (r < 0 && errno == EINTR) {
          rbuf.clear();
          continue;
        }
        if (r == 0) {
          rbuf.clear();
          stopped(RawlogStop::kLimit,
                  "no result for " + std::to_string(limits.stall_seconds) + " s: the sandbox was stopped");
          return false;
        }
        const ssize_t k = ::read(fd, rbuf.data(), rbuf.size());
        if (k < 0 && errno == EINTR) {
          rbuf.clear();
          continue;
        }
        if (k <= 0) {
          rbuf.clear();
          died();
          return false;
        }
        rbuf.resize(static_cast<std::size_t>(k));
      }
      const std::size_t take = std::min(n, rbuf.size() - rpos);
      std::memcpy(p, rbuf.data() + rpos, take);
      rpos += take;
      p += take;
      n -= take;
    }
    return true;
  }

  void stopped(RawlogStop kind, const std::string& why) {
    status.stop = kind;
    status.objects = progress->index;
    status.offset = progress->offset;
    const std::string cls(progress->class_name, std::min<std::size_t>(progress->class_len, kMaxClassName));
    status.reason = (cls.empty() ? "" : cls + ": ") + why;
    end_child();
  }

  void died() {
    int st = 0;
    pid_t r;
    while ((r = ::waitpid(pid, &st, 0)) < 0 && errno == EINTR) {}
    pid = -1;
    std::string why = "the sandbox ended without a result";
    RawlogStop kind = RawlogStop::kCorrupt;
    if (r > 0 && WIFSIGNALED(st)) {
      const int sig = WTERMSIG(st);
      if (sig == SIGXCPU) {
        kind = RawlogStop::kLimit;
        why = "MRPT's parser used more than " + std::to_string(limits.cpu_seconds) + " s of CPU in the sandbox";
      } else {
        why = "MRPT's parser crashed in the sandbox (" + std::string(sigabbrev_np(sig) ? sigabbrev_np(sig) : "signal") +
              ", signal " + std::to_string(sig) + ")";
      }
    } else if (r > 0 && WIFEXITED(st)) {
      why = "the sandbox ended without a result (exit code " + std::to_string(WEXITSTATUS(st)) +
            "): MRPT's parser failed there";
    }
    stopped(kind, why);
  }
};

ObjectSandbox::ObjectSandbox(const SandboxLimits& limits) : impl_(std::make_unique<Impl>()) { impl_->limits = limits; }
ObjectSandbox::~ObjectSandbox() = default;

void ObjectSandbox::start(const SandboxJob& job, const RawlogReaderOptions& options) {
  Impl& s = *impl_;
  if (s.job_active) s.end_child();  // an abandoned job: its child may still be writing
  s.status = RawlogReadStatus{};
  s.status.objects = job.index;
  s.status.offset = job.offset;
  if (s.pid < 0) s.fork_child();
  s.progress->index = job.index;
  s.progress->offset = job.offset;
  s.progress->class_len = 0;
  std::string body;
  put<std::uint8_t>(body, job.from_file ? 1 : 0);
  put<std::uint64_t>(body, job.offset);
  put<std::int64_t>(body, job.index);
  put<std::uint64_t>(body, options.max_object_bytes);
  put<std::uint64_t>(body, options.max_string_bytes);
  put<std::uint64_t>(body, options.max_total_bytes);
  body += job.from_file ? job.path : job.bytes;
  std::string msg;
  put<std::uint64_t>(msg, body.size());
  msg += body;
  s.job_active = true;
  if (!write_all(s.fd, msg.data(), msg.size())) s.died();
}

std::optional<RawlogObject> ObjectSandbox::next() {
  Impl& s = *impl_;
  if (!s.job_active) return std::nullopt;
  std::uint8_t type = 0;
  if (!s.receive(&type, 1)) return std::nullopt;
  const auto length = [&](std::size_t max, std::uint64_t& n) {
    if (!s.receive(&n, sizeof n)) return false;
    if (n > max) {
      s.stopped(RawlogStop::kCorrupt, "the sandbox sent a malformed message");
      return false;
    }
    return true;
  };
  if (type == kMsgObject) {
    RawlogObject o;
    std::uint64_t n = 0, end_offset = 0;
    if (!s.receive(&o.index, sizeof o.index) || !s.receive(&o.offset, sizeof o.offset) ||
        !s.receive(&end_offset, sizeof end_offset) || !length(kMaxClassName, n)) {
      return std::nullopt;
    }
    o.class_name.resize(n);
    if (!s.receive(o.class_name.data(), n) || !length(std::size_t{1} << 32, n)) return std::nullopt;
    o.bytes.resize(n);
    if (!s.receive(o.bytes.data(), n)) return std::nullopt;
    try {
      o.object = deserialize(o.bytes);
    } catch (const std::exception& e) {
      s.stopped(RawlogStop::kCorrupt, std::string("MRPT could not read the sandbox's copy: ") + e.what());
      return std::nullopt;
    }
    s.status.objects = o.index + 1;
    s.status.offset = end_offset;
    return o;
  }
  if (type == kMsgStatus) {
    std::uint8_t stop = 0;
    std::uint64_t n = 0;
    if (!s.receive(&stop, 1) || !s.receive(&s.status.objects, sizeof s.status.objects) ||
        !s.receive(&s.status.offset, sizeof s.status.offset) || !length(kMaxReason, n)) {
      return std::nullopt;
    }
    s.status.reason.resize(n);
    if (!s.receive(s.status.reason.data(), n)) return std::nullopt;
    s.status.stop =
        stop <= static_cast<std::uint8_t>(RawlogStop::kLimit) ? static_cast<RawlogStop>(stop) : RawlogStop::kCorrupt;
    s.job_active = false;
    return std::nullopt;
  }
  s.stopped(RawlogStop::kCorrupt, "the sandbox sent a malformed message");
  return std::nullopt;
}

const RawlogReadStatus& ObjectSandbox::status() const { return impl_->status; }

const SandboxLimits& ObjectSandbox::limits() const { return impl_->limits; }

bool ObjectSandbox::reusable() const { return impl_->pid > 0 && !impl_->job_active; }

namespace {
std::mutex pool_mutex;
std::vector<std::unique_ptr<ObjectSandbox>>& pool() {
  static std::vector<std::unique_ptr<ObjectSandbox>> p;
  return p;
}
}  // namespace

std::unique_ptr<ObjectSandbox> acquire_sandbox(const SandboxLimits& limits) {
  {
    const std::lock_guard<std::mutex> lock(pool_mutex);
    auto& p = pool();
    if (!p.empty()) {
      std::unique_ptr<ObjectSandbox> s = std::move(p.back());
      p.pop_back();
      const SandboxLimits& l = s->limits();
      if (l.memory_bytes == limits.memory_bytes && l.cpu_seconds == limits.cpu_seconds &&
          l.stall_seconds == limits.stall_seconds) {
        return s;
      }
    }
  }
  return std::make_unique<ObjectSandbox>(limits);
}

void release_sandbox(std::unique_ptr<ObjectSandbox> sandbox) {
  if (!sandbox || !sandbox->reusable()) return;
  const std::lock_guard<std::mutex> lock(pool_mutex);
  if (pool().size() < 4) pool().push_back(std::move(sandbox));
}

}  // namespace losmimo::rawlog_io
