#include "losmimo/fusion/rawlog/io/source.h"

#include <zlib.h>

#include <algorithm>
#include <cstring>

namespace losmimo::rawlog_io {

namespace {

struct GzClose {
  void operator()(gzFile_s* f) const { gzclose(f); }
};

class GzFileSource : public RawlogByteSource {
 public:
  explicit GzFileSource(const std::string& path) : file_(gzopen(path.c_str(), "rb")) {
    if (!file_) throw std::runtime_error(path + ": cannot open rawlog");
  }
  std::size_t read(std::uint8_t* dst, std::size_t n) override {
    const int got = gzread(file_.get(), dst, static_cast<unsigned>(n));
    int code = Z_OK;
    const char* msg = gzerror(file_.get(), &code);
    if (got < 0 || (got == 0 && code != Z_OK)) {
      throw RawlogSourceError(std::string("gzip: ") + (msg ? msg : "read error"), code == Z_BUF_ERROR);
    }
    return static_cast<std::size_t>(got);
  }

 private:
  std::unique_ptr<gzFile_s, GzClose> file_;
};

class MemorySource : public RawlogByteSource {
 public:
  explicit MemorySource(std::string bytes) : bytes_(std::move(bytes)) {
    gzip_ = bytes_.size() >= 2 && static_cast<unsigned char>(bytes_[0]) == 0x1f &&
            static_cast<unsigned char>(bytes_[1]) == 0x8b;
    if (gzip_) {
      std::memset(&z_, 0, sizeof z_);
      if (inflateInit2(&z_, 15 + 16) != Z_OK) throw std::runtime_error("zlib: inflateInit2 failed");
      z_.next_in = reinterpret_cast<Bytef*>(bytes_.data());
      z_.avail_in = static_cast<uInt>(bytes_.size());
    }
  }
  ~MemorySource() override {
    if (gzip_) inflateEnd(&z_);
  }
  std::size_t read(std::uint8_t* dst, std::size_t n) override {
    if (!gzip_) {
      const std::size_t k = std::min(n, bytes_.size() - pos_);
      std::memcpy(dst, bytes_.data() + pos_, k);
      pos_ += k;
      return k;
    }
    if (ended_) return 0;
    z_.next_out = dst;
    z_.avail_out = static_cast<uInt>(n);
    while (z_.avail_out > 0) {
      const int rc = inflate(&z_, Z_NO_FLUSH);
      if (rc == Z_STREAM_END) {
        ended_ = true;  // trailing bytes after the gzip member are ignored, as gzread does
        break;
      }
      if (rc == Z_BUF_ERROR && z_.avail_in == 0) {
        if (z_.avail_out == n) throw RawlogSourceError("gzip: unexpected end of file", true);
        break;  // return what we have; the next call reports the truncation
      }
      if (rc != Z_OK) throw RawlogSourceError(std::string("gzip: ") + (z_.msg ? z_.msg : "data error"), false);
    }
    return n - z_.avail_out;
  }

 private:
  std::string bytes_;
  bool gzip_ = false, ended_ = false;
  std::size_t pos_ = 0;
  z_stream z_{};
};

}  // namespace

std::unique_ptr<RawlogByteSource> open_rawlog_file_source(const std::string& path) {
  return std::make_unique<GzFileSource>(path);
}

std::unique_ptr<RawlogByteSource> make_rawlog_memory_source(std::string bytes) {
  return std::make_unique<MemorySource>(std::move(bytes));
}

}  // namespace losmimo::rawlog_io
