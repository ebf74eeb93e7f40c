#include "losmimo/fusion/rawlog/io/reader.h"

#include "losmimo/fusion/rawlog/io/sandbox.h"
#include "losmimo/fusion/rawlog/io/source.h"
#include "object_bytes.h"
#include "object_scanner.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/serialization/CArchive.h>

namespace losmimo::rawlog_io {

namespace {

constexpr std::size_t kChunk = 64 * 1024;

using detail::calibration;
using detail::kEndFlag;
using detail::Stop;

std::string first_line(const std::string& s) {
  std::string out;
  std::istringstream in(s);
  for (std::string line; std::getline(in, line);) {
    if (line.find_first_not_of(" \t=") == std::string::npos) continue;
    out = line;
    // MRPT's traces: headers ("Original exception:", "==== MRPT exception ====") are skipped.
    if (line.find("Exception") == std::string::npos && line.find("==") == std::string::npos &&
        line.find("xception:") == std::string::npos) {
      break;
    }
  }
  return out.empty() ? s : out;
}

}  // namespace

std::string to_string(RawlogStop stop) {
  switch (stop) {
    case RawlogStop::kNone:
      return "reading";
    case RawlogStop::kEnd:
      return "end";
    case RawlogStop::kTruncated:
      return "truncated";
    case RawlogStop::kCorrupt:
      return "corrupt";
    case RawlogStop::kLimit:
      return "limit";
  }
  return "?";
}

std::string RawlogReadStatus::describe() const {
  std::ostringstream o;
  if (stop == RawlogStop::kEnd) {
    o << "end of file after " << objects << " objects (" << offset << " bytes)";
  } else {
    o << "stopped at object " << objects << " (uncompressed byte " << offset << "): " << to_string(stop) << ": "
      << reason;
  }
  return o.str();
}

struct RawlogReader::Impl final : detail::ObjectWindow {
  RawlogReaderOptions options;
  std::unique_ptr<RawlogByteSource> source;
  // Where the sandbox's child reads the same log from (the file, or a copy of the bytes).
  SandboxJob job;
  SandboxChannel* channel = nullptr;  // in the sandbox's child: told before each MRPT parse
  bool ours = false;                  // object 0 is losmimo's CONFIG
  bool to_sandbox = false;            // foreign: the objects from here on go to the sandbox
  std::unique_ptr<ObjectSandbox> sandbox;
  std::vector<std::uint8_t> buf;
  std::size_t head = 0;        // start of the current object in buf
  std::uint64_t buf_base = 0;  // absolute offset of buf[0]
  bool source_ended = false;
  RawlogReadStatus status;

  // At least k bytes from head buffered? Reads more as needed.
  bool ensure(std::size_t k) override {
    while (buf.size() - head < k) {
      if (source_ended) return false;
      if (head > 0 && head >= buf.size() / 2) {  // drop consumed bytes
        buf.erase(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(head));
        buf_base += head;
        head = 0;
      }
      const std::size_t old = buf.size();
      buf.resize(old + kChunk);
      std::size_t got = 0;
      try {
        got = source->read(buf.data() + old, kChunk);
      } catch (const RawlogSourceError& e) {
        buf.resize(old);
        throw Stop{e.truncated ? RawlogStop::kTruncated : RawlogStop::kCorrupt, e.what()};
      }
      buf.resize(old + got);
      if (got == 0) source_ended = true;
      if (buf_base + buf.size() > options.max_total_bytes) {
        throw Stop{RawlogStop::kLimit, "the log is larger than max_total_bytes (" +
                                           std::to_string(options.max_total_bytes) + " bytes uncompressed)"};
      }
    }
    return true;
  }

  const std::uint8_t* data() const override { return buf.data() + head; }

  // The whole length of the object at head if its class is one the scanner knows
  // (scanned_classes.cpp); nullopt otherwise (class name in `name`).
  std::optional<std::size_t> scan(std::string& name) {
    detail::ObjectCursor c(*this, options);
    const std::uint8_t len = c.u8();
    if (!(len & 0x80)) throw Stop{RawlogStop::kCorrupt, "object header without the MRPT >= 0.5.5 flag"};
    const std::size_t name_len = len & 0x7F;
    if (name_len == 0 || name_len > 120) throw Stop{RawlogStop::kCorrupt, "bad class name length"};
    c.need(name_len);
    name.assign(reinterpret_cast<const char*>(c.at()), name_len);
    for (char ch : name) {
      if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == ':'))
        throw Stop{RawlogStop::kCorrupt, "bad class name"};
    }
    c.skip(name_len);
    const std::uint8_t version = c.u8();
    // MRPT 2 names classes with their namespace; older files without it.
    const std::string prefix = "mrpt::obs::";
    const std::string cls = name.compare(0, prefix.size(), prefix) == 0 ? name.substr(prefix.size()) : name;
    const detail::ScannedClass* row = detail::find_scanned_class(cls, version);
    if (!row) return std::nullopt;
    row->scan(c, calibration(), version);
    if (c.u8() != kEndFlag) throw Stop{RawlogStop::kCorrupt, "end-of-object flag missing in " + name};
    return c.pos();
  }

  // MRPT reads an unscanned object straight from the buffer and the source.
  class Adapter : public mrpt::io::CStream {
   public:
    explicit Adapter(Impl& r) : r_(r) {}
    size_t Read(void* dst, size_t n) override {
      if (!r_.ensure(pos_ + n)) n = r_.buf.size() - r_.head - pos_;
      std::memcpy(dst, r_.buf.data() + r_.head + pos_, n);
      pos_ += n;
      return n;
    }
    size_t Write(const void*, size_t) override { return 0; }
    uint64_t Seek(int64_t, TSeekOrigin) override { throw std::runtime_error("not seekable"); }
    uint64_t getTotalBytesCount() const override { return 0; }
    uint64_t getPosition() const override { return pos_; }
    std::size_t consumed() const { return pos_; }

   private:
    Impl& r_;
    std::size_t pos_ = 0;
  };

  // Hands the rest of the log, from the current object on, to a sandbox.
  void start_sandbox() {
    to_sandbox = false;
    sandbox = acquire_sandbox(options.sandbox);
    SandboxJob j = job;
    j.offset = buf_base + head;
    j.index = status.objects;
    sandbox->start(j, options);
  }

  std::optional<RawlogObject> from_sandbox() {
    std::optional<RawlogObject> o = sandbox->next();
    status.objects = sandbox->status().objects;
    status.offset = sandbox->status().offset;
    if (!o) {
      status = sandbox->status();
      if (status.stop == RawlogStop::kNone) status.stop = RawlogStop::kCorrupt;
      release_sandbox(std::move(sandbox));
      sandbox.reset();
    }
    return o;
  }

  std::optional<RawlogObject> next() {
    if (sandbox) return from_sandbox();
    if (status.stop != RawlogStop::kNone) return std::nullopt;
    RawlogObject out;
    out.index = status.objects;
    out.offset = buf_base + head;
    status.offset = out.offset;
    try {
      if (!ensure(1)) {
        status.stop = RawlogStop::kEnd;
        return std::nullopt;
      }
      if (to_sandbox) {
        start_sandbox();
        return from_sandbox();
      }
      const std::optional<std::size_t> size = scan(out.class_name);
      if (channel) channel->parsing(out.index, out.offset, out.class_name);
      std::size_t n = 0;
      if (size) {
        n = *size;
        mrpt::io::CMemoryStream mem;
        mem.assignMemoryNotOwn(buf.data() + head, n);
        auto a = mrpt::serialization::archiveFrom(mem);
        out.object = a.ReadObject();
        if (mem.getPosition() != n) throw Stop{RawlogStop::kCorrupt, "MRPT read a different length"};
      } else if (options.foreign == ForeignObjects::kInProcess) {
        Adapter in(*this);
        auto a = mrpt::serialization::archiveFrom(in);
        out.object = a.ReadObject();
        n = in.consumed();
      } else if (options.foreign == ForeignObjects::kSandbox && !ours) {
        start_sandbox();
        return from_sandbox();
      } else if (ours) {
        throw Stop{RawlogStop::kLimit, "class " + out.class_name + " in a losmimo rawlog, which never holds one"};
      } else {
        throw Stop{RawlogStop::kLimit, "class " + out.class_name + " is not one the reader can bound"};
      }
      if (out.index == 0) {
        const auto* c = dynamic_cast<const mrpt::obs::CObservationComment*>(out.object.get());
        const std::string magic = std::string(kRawlogMagic) + " ";
        ours = c && c->text.compare(0, magic.size(), magic) == 0;
        to_sandbox = !ours && options.foreign == ForeignObjects::kSandbox;
      }
      out.bytes.assign(buf.begin() + static_cast<std::ptrdiff_t>(head),
                       buf.begin() + static_cast<std::ptrdiff_t>(head + n));
      head += n;
      ++status.objects;
      status.offset = buf_base + head;
      return out;
    } catch (const Stop& s) {
      status.stop = s.kind;
      status.reason = (out.class_name.empty() ? "" : out.class_name + ": ") + s.reason;
    } catch (const std::bad_alloc&) {
      status.stop = RawlogStop::kLimit;
      status.reason = out.class_name + ": out of memory while MRPT parsed it";
    } catch (const std::exception& e) {
      // MRPT throws on EOF inside an object and on bad content alike: tell them apart by
      // whether the source ran dry.
      status.stop = source_ended ? RawlogStop::kTruncated : RawlogStop::kCorrupt;
      status.reason = out.class_name + ": MRPT: " + first_line(e.what());
    } catch (...) {
      status.stop = RawlogStop::kCorrupt;
      status.reason = out.class_name + ": MRPT threw a non-standard exception";
    }
    return std::nullopt;
  }
};

RawlogReader::RawlogReader(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
RawlogReader::RawlogReader(RawlogReader&&) noexcept = default;
RawlogReader& RawlogReader::operator=(RawlogReader&&) noexcept = default;
RawlogReader::~RawlogReader() = default;

RawlogReader RawlogReader::open_file(const std::string& path, const RawlogReaderOptions& options) {
  calibration();
  auto impl = std::make_unique<Impl>();
  impl->options = options;
  impl->source = open_rawlog_file_source(path);
  impl->job.from_file = true;
  impl->job.path = path;
  return RawlogReader(std::move(impl));
}

RawlogReader RawlogReader::from_bytes(std::string bytes, const RawlogReaderOptions& options) {
  calibration();
  auto impl = std::make_unique<Impl>();
  impl->options = options;
  impl->job.from_file = false;
  if (options.foreign == ForeignObjects::kSandbox) impl->job.bytes = bytes;  // for the sandbox's child
  impl->source = make_rawlog_memory_source(std::move(bytes));
  return RawlogReader(std::move(impl));
}

RawlogReadStatus run_sandbox_job(const SandboxJob& job, const RawlogReaderOptions& options, SandboxChannel& channel) {
  calibration();
  RawlogReader::Impl r;
  r.options = options;
  r.options.foreign = ForeignObjects::kInProcess;
  r.channel = &channel;
  r.status.objects = job.index;
  r.status.offset = job.offset;
  try {
    r.source = job.from_file ? open_rawlog_file_source(job.path) : make_rawlog_memory_source(job.bytes);
    // Skip to the job's first object (the parent read the ones before it).
    std::vector<std::uint8_t> scratch(64 * 1024);
    for (std::uint64_t left = job.offset; left > 0;) {
      const std::size_t got =
          r.source->read(scratch.data(), static_cast<std::size_t>(std::min<std::uint64_t>(left, scratch.size())));
      if (got == 0) throw RawlogSourceError("the log ended before the sandbox's first object", true);
      left -= got;
    }
  } catch (const RawlogSourceError& e) {
    r.status.stop = e.truncated ? RawlogStop::kTruncated : RawlogStop::kCorrupt;
    r.status.reason = e.what();
    return r.status;
  }
  r.buf_base = job.offset;
  while (std::optional<RawlogObject> o = r.next()) {
    std::string why;
    if (!channel.send(*o, r.status.offset, why)) {
      r.status.stop = RawlogStop::kLimit;
      r.status.objects = o->index;
      r.status.offset = o->offset;
      r.status.reason = why;
      break;
    }
  }
  return r.status;
}

std::optional<RawlogObject> RawlogReader::next() { return impl_->next(); }
const RawlogReadStatus& RawlogReader::status() const { return impl_->status; }

RawlogContents read_rawlog_bytes(std::string bytes, const RawlogReaderOptions& options) {
  RawlogReader reader = RawlogReader::from_bytes(std::move(bytes), options);
  RawlogContents out;
  while (auto o = reader.next()) out.objects.push_back(std::move(*o));
  out.status = reader.status();
  return out;
}

}  // namespace losmimo::rawlog_io
