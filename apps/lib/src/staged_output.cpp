#include "losmimo/apps/lib/staged_output.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "losmimo/placement/common/bounded_read.h"
#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/hash.h"
#include "losmimo/placement/common/test_hook.h"

namespace losmimo::apps {

namespace fs = std::filesystem;
using common::fnv1a64;
using common::format_hex64;
using common::IniConfig;
using common::InputError;
using common::kFnvOffset;
using common::test_pause_point;

namespace {

std::runtime_error io_error(const std::string& what, const fs::path& p) {
  return std::runtime_error(p.string() + ": " + what + ": " + std::strerror(errno));
}

// Absolute, normalised, without a trailing separator ("results/" -> ".../results").
fs::path normalised(const std::string& path) {
  if (path.empty()) throw InputError("'': an output path is required");
  fs::path p = fs::absolute(fs::path(path)).lexically_normal();
  if (!p.has_filename()) p = p.parent_path();
  if (p == p.root_path() || p.filename() == "." || p.filename() == "..") {
    throw InputError(path + ": not a folder a run can be renamed into");
  }
  return p;
}

void fsync_path(const fs::path& p, bool directory) {
  const int fd = ::open(p.c_str(), (directory ? O_DIRECTORY : 0) | O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw io_error("cannot open to sync", p);
  const int rc = ::fsync(fd);
  ::close(fd);
  if (rc != 0) throw io_error("fsync failed", p);
}

// Size and FNV-1a digest of a file's bytes.
std::pair<std::uintmax_t, std::uint64_t> size_and_digest(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw std::runtime_error(p.string() + ": cannot read");
  std::uint64_t h = kFnvOffset;
  std::uintmax_t n = 0;
  std::vector<char> buf(1 << 16);
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    const auto got = static_cast<std::size_t>(in.gcount());
    h = fnv1a64(buf.data(), got, h);
    n += got;
  }
  if (in.bad()) throw std::runtime_error(p.string() + ": read error");
  return {n, h};
}

// Files losmimo apps wrote into their folders before folders had a manifest.
bool legacy_output_name(const std::string& name) {
  static const std::set<std::string> kNames = {"config.ini", "shard.ini",     "records.csv", "records.partial",
                                               "trials.csv", "positions.csv", "traces.csv",  "summary.csv",
                                               "report.md",  "estimates.csv", "epochs.csv"};
  if (kNames.count(name)) return true;
  const auto ends_with = [&](const std::string& s) {
    return name.size() >= s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0;
  };
  if (ends_with(".partial") || ends_with(".tmp")) return true;
  for (const char* stem : {"fig", "coeval_", "outage"}) {
    if (name.rfind(stem, 0) != 0) continue;
    for (const char* ext : {".png", ".gp", ".dat", ".log"}) {
      if (ends_with(ext)) return true;
    }
  }
  return false;
}

// The [files] entries of a manifest: name -> "size digest".
std::vector<std::pair<std::string, std::string>> listed_files(const IniConfig& manifest, const fs::path& dir) {
  std::vector<std::pair<std::string, std::string>> files;
  const long long count = manifest.get_integer("files", "count", 0, 0, 1'000'000);
  for (long long i = 1; i <= count; ++i) {
    const std::string key = "file_" + std::to_string(i);
    if (!manifest.has("files", key)) throw InputError((dir / kManifestName).string() + ": [files] " + key + " missing");
    const std::string entry = manifest.get_string("files", key, "");
    const std::size_t space = entry.find(' ');
    if (space == std::string::npos || space == 0) {
      throw InputError(manifest.where("files", key) + ": '" + entry + "': expected '<name> <bytes> <digest>'");
    }
    files.emplace_back(entry.substr(0, space), entry.substr(space + 1));
  }
  return files;
}

// Takes the lock of a staging folder; -1 with errno EWOULDBLOCK if another process holds it.
int lock_folder(const fs::path& p) {
  const int fd = ::open(p.c_str(), O_DIRECTORY | O_RDONLY | O_CLOEXEC);
  if (fd < 0) return -1;
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int e = errno;
    ::close(fd);
    errno = e;
    return -1;
  }
  return fd;
}

// Renames `from` to `to` where `to` must not exist; false (errno EEXIST) if it does.
bool rename_noreplace(const fs::path& from, const fs::path& to) {
  if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_NOREPLACE) == 0) return true;
  if (errno != EINVAL && errno != ENOSYS) return false;
  // A file system without renameat2 flags: link + unlink for files; for folders rename()
  // refuses a non-empty target and replaces only an empty one.
  if (fs::is_directory(from)) {
    if (fs::exists(to)) {
      errno = EEXIST;
      return false;
    }
    return ::rename(from.c_str(), to.c_str()) == 0;
  }
  if (::link(from.c_str(), to.c_str()) != 0) return false;
  ::unlink(from.c_str());
  return true;
}

}  // namespace

ExistingOutput inspect_output(const fs::path& path) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(path, ec);
  if (ec || !fs::exists(st)) return {ExistingOutput::kAbsent, ""};
  if (fs::is_symlink(st)) return {ExistingOutput::kNotOurs, "a symbolic link"};
  if (!fs::is_directory(st)) return {ExistingOutput::kNotOurs, "a file, not a folder"};
  std::vector<std::string> names;
  bool subfolder = false;
  for (const fs::directory_entry& e : fs::directory_iterator(path, ec)) {
    names.push_back(e.path().filename().string());
    subfolder = subfolder || !e.is_regular_file();
  }
  if (ec) return {ExistingOutput::kNotOurs, "a folder that cannot be read"};
  if (names.empty()) return {ExistingOutput::kEmptyFolder, "an empty folder"};
  std::sort(names.begin(), names.end());
  const std::string some =
      names.front() + (names.size() > 1 ? ", " + names[1] : "") + (names.size() > 2 ? ", ..." : "");
  if (fs::exists(path / kManifestName)) {
    try {
      const IniConfig m = read_manifest(path);
      std::set<std::string> listed = {kManifestName};
      for (const auto& [name, rest] : listed_files(m, path)) listed.insert(name);
      std::vector<std::string> extra;
      for (const std::string& n : names) {
        if (!listed.count(n)) extra.push_back(n);
      }
      const std::string what = "a finished " + m.get_string("run", "kind", "run") + " (" + kManifestName + ", " +
                               std::to_string(listed.size() - 1) + " files)";
      if (!extra.empty()) {
        return {ExistingOutput::kNotOurs, what + " and files that are not part of it (" + extra.front() +
                                              (extra.size() > 1 ? ", ..." : "") + ")"};
      }
      return {ExistingOutput::kOurs, what};
    } catch (const InputError& e) {
      return {ExistingOutput::kNotOurs, "a folder whose " + std::string(kManifestName) + " is damaged"};
    }
  }
  const bool all_ours = !subfolder && std::all_of(names.begin(), names.end(), legacy_output_name);
  if (all_ours) {
    return {ExistingOutput::kOurs, "results of a losmimo run (" + some + ")"};
  }
  return {ExistingOutput::kNotOurs, "a folder that is not a losmimo output (" + some + ")"};
}

IniConfig read_manifest(const fs::path& dir) {
  const fs::path p = dir / kManifestName;
  if (!fs::exists(p)) throw InputError(dir.string() + ": no " + kManifestName + " (not a finished run)");
  IniConfig m = IniConfig::from_file(p.string());
  if (m.get_integer("run", "format", 0, 0, 1'000'000) != 1) {
    throw InputError(p.string() + ": [run] format = " + m.get_string("run", "format", "(missing)") +
                     ": not one this version reads (1)");
  }
  if (!m.has("run", "kind")) throw InputError(p.string() + ": [run] kind missing");
  return m;
}

void verify_manifest_files(const fs::path& dir, const IniConfig& manifest) {
  for (const auto& [name, expected] : listed_files(manifest, dir)) {
    const fs::path p = dir / name;
    if (!fs::is_regular_file(p)) throw InputError(p.string() + ": missing (listed in " + kManifestName + ")");
    // The size first: a file of another size is not read (it may be huge).
    const std::string listed_size = expected.substr(0, expected.find(' '));
    if (std::to_string(fs::file_size(p)) != listed_size) {
      throw InputError(p.string() + ": changed since the run wrote it (" + std::to_string(fs::file_size(p)) +
                       " bytes; " + kManifestName + " says " + listed_size + ")");
    }
    const auto [size, digest] = size_and_digest(p);
    if (expected != std::to_string(size) + " " + format_hex64(digest)) {
      throw InputError(p.string() + ": changed since the run wrote it (" + std::to_string(size) + " bytes, digest " +
                       format_hex64(digest) + "; " + kManifestName + " says '" + expected + "')");
    }
  }
}

// ---- StagedDir ----

fs::path StagedDir::staging_path_of(const std::string& final_dir) {
  const fs::path f = normalised(final_dir);
  return f.parent_path() / (f.filename().string() + kStagingSuffix);
}

StagedDir::StagedDir(fs::path final_dir, fs::path staging, int lock_fd, bool replace)
    : final_(std::move(final_dir)), staging_(std::move(staging)), lock_fd_(lock_fd), replace_(replace) {}

StagedDir::StagedDir(StagedDir&& other) noexcept
    : final_(std::move(other.final_)),
      staging_(std::move(other.staging_)),
      lock_fd_(other.lock_fd_),
      replace_(other.replace_) {
  other.lock_fd_ = -1;
}

StagedDir::~StagedDir() {
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

namespace {
void check_final(const fs::path& final_dir, bool replace) {
  const fs::path cwd = fs::current_path();
  const auto [a, b] = std::mismatch(final_dir.begin(), final_dir.end(), cwd.begin(), cwd.end());
  if (a == final_dir.end()) throw InputError(final_dir.string() + ": is the current folder or contains it");
  const ExistingOutput e = inspect_output(final_dir);
  if (e.kind == ExistingOutput::kNotOurs) throw OutputExistsError(final_dir.string() + " is " + e.description, false);
  if (e.kind == ExistingOutput::kOurs && !replace)
    throw OutputExistsError(final_dir.string() + " holds " + e.description, true);
}
}  // namespace

void StagedDir::check(const std::string& final_dir, bool replace, StaleStaging stale) {
  check_final(normalised(final_dir), replace);
  const fs::path staging = staging_path_of(final_dir);
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(staging, ec))) return;
  if (!fs::is_directory(fs::symlink_status(staging, ec))) {
    throw OutputExistsError(staging.string() + " is in the way (not a folder)", false);
  }
  const int fd = lock_folder(staging);
  if (fd < 0) throw OutputExistsError(staging.string() + " is in use by a running process", false);
  ::close(fd);
  if (stale == StaleStaging::kRefuse && !replace)
    throw OutputExistsError(staging.string() + " holds an interrupted run", true, final_dir);
}

StagedDir StagedDir::create(const std::string& final_dir, bool replace, StaleStaging stale) {
  check(final_dir, replace, stale);
  const fs::path final_path = normalised(final_dir);
  const fs::path staging = staging_path_of(final_dir);
  // An interrupted run's staging folder that may go (checked above), removed under its lock.
  std::error_code ec;
  if (fs::exists(fs::symlink_status(staging, ec))) {
    const int old = lock_folder(staging);
    if (old < 0) throw OutputExistsError(staging.string() + " is in use by a running process", false);
    fs::remove_all(staging);
    ::close(old);
  }
  // Created under a private name, locked, then renamed: the staging folder never exists unlocked.
  const fs::path tmp = final_path.parent_path() /
                       (final_path.filename().string() + kStagingSuffix + ".tmp" + std::to_string(::getpid()));
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  const int fd = lock_folder(tmp);
  if (fd < 0) throw io_error("cannot lock", tmp);
  if (!rename_noreplace(tmp, staging)) {
    ::close(fd);
    fs::remove_all(tmp);
    throw OutputExistsError(staging.string() + " is in use by a running process", false);
  }
  return StagedDir(final_path, staging, fd, replace);
}

StagedDir StagedDir::resume(const std::string& final_dir, bool replace) {
  const fs::path final_path = normalised(final_dir);
  const fs::path staging = staging_path_of(final_dir);
  if (!fs::is_directory(staging)) throw InputError(staging.string() + ": missing");
  check_final(final_path, replace);
  const int fd = lock_folder(staging);
  if (fd < 0) throw OutputExistsError(staging.string() + " is in use by a running process", false);
  return StagedDir(final_path, staging, fd, replace);
}

void StagedDir::publish(const Manifest& manifest) {
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(staging_)) {
    if (e.path().filename() == kManifestName) continue;
    if (!e.is_regular_file()) throw std::runtime_error(e.path().string() + ": not a file (staging holds files only)");
    files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  std::ostringstream m;
  m << "# losmimo run manifest: written last, once every file below was complete. A folder\n"
    << "# without it holds no finished run.\n[run]\nformat = 1\nkind = " << manifest.kind << "\n";
  for (const auto& [k, v] : manifest.run_keys) m << k << " = " << v << "\n";
  m << manifest.extra_sections;
  m << "\n[files]\ncount = " << files.size() << "\n";
  for (std::size_t i = 0; i < files.size(); ++i) {
    fsync_path(files[i], false);
    const auto [size, digest] = size_and_digest(files[i]);
    m << "file_" << i + 1 << " = " << files[i].filename().string() << " " << size << " " << format_hex64(digest)
      << "\n";
  }
  const fs::path manifest_path = staging_ / kManifestName;
  {
    std::ofstream out(manifest_path, std::ios::binary | std::ios::trunc);
    out << m.str();
    out.flush();
    if (!out) throw std::runtime_error(manifest_path.string() + ": write failed");
  }
  fsync_path(manifest_path, false);
  fsync_path(staging_, true);
  test_pause_point("staged.before_rename");

  const ExistingOutput now = inspect_output(final_);
  const std::string kept = "; the finished outputs are in " + staging_.string();
  if (now.kind == ExistingOutput::kAbsent) {
    if (!rename_noreplace(staging_, final_)) {
      throw OutputExistsError(final_.string() + " appeared while the run was under way" + kept, false);
    }
  } else if (now.kind == ExistingOutput::kEmptyFolder || (now.kind == ExistingOutput::kOurs && replace_)) {
    // Swap in one step, then remove the old run (now under the staging name).
    if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, final_.c_str(), RENAME_EXCHANGE) != 0) {
      if (errno != EINVAL && errno != ENOSYS) throw io_error("cannot rename into place" + kept, final_);
      const fs::path old = final_.parent_path() / (final_.filename().string() + ".old" + std::to_string(::getpid()));
      fs::rename(final_, old);
      fs::rename(staging_, final_);
      fs::remove_all(old);
    } else {
      fs::remove_all(staging_);
    }
  } else {
    throw OutputExistsError(final_.string() + (now.kind == ExistingOutput::kOurs ? " holds " : " is ") +
                                now.description + " (it appeared while the run was under way)" + kept,
                            false);
  }
  fsync_path(final_.parent_path(), true);
  ::close(lock_fd_);
  lock_fd_ = -1;
}

// ---- StagedFile ----

StagedFile::StagedFile(std::string final_path, std::string staging, int fd, bool replace)
    : final_(std::move(final_path)), staging_(std::move(staging)), fd_(fd), replace_(replace) {}

StagedFile::StagedFile(StagedFile&& other) noexcept
    : final_(std::move(other.final_)), staging_(std::move(other.staging_)), fd_(other.fd_), replace_(other.replace_) {
  other.fd_ = -1;
}

StagedFile::~StagedFile() {
  if (fd_ >= 0) ::close(fd_);
}

namespace {
// What is at a file output path; throws OutputExistsError unless it may be written.
void check_final_file(const fs::path& p, bool replace) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(p, ec);
  if (ec || !fs::exists(st)) return;
  if (!fs::is_regular_file(st)) throw OutputExistsError(p.string() + " is in the way (not a regular file)", false);
  if (!replace) {
    throw OutputExistsError(p.string() + " holds a file (" + std::to_string(fs::file_size(p, ec)) + " bytes)", true);
  }
}
}  // namespace

StagedFile StagedFile::create(const std::string& final_path, bool replace) {
  const fs::path f = normalised(final_path);
  check_final_file(f, replace);
  const std::string staging = f.string() + kStagingSuffix;
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(staging, ec);
  if (fs::exists(st) && !fs::is_regular_file(st))
    throw OutputExistsError(staging + " is in the way (not a regular file)", false);
  const int fd = ::open(staging.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw io_error("cannot create", staging);
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd);
    throw OutputExistsError(staging + " is in use by a running process", false);
  }
  if (::ftruncate(fd, 0) != 0) {
    ::close(fd);
    throw io_error("cannot truncate", staging);
  }
  return StagedFile(f.string(), staging, fd, replace);
}

void StagedFile::publish() {
  if (::fsync(fd_) != 0) throw io_error("fsync failed", staging_);
  test_pause_point("staged.before_rename");
  check_final_file(final_, replace_);
  if (replace_) {
    if (::rename(staging_.c_str(), final_.c_str()) != 0) throw io_error("cannot rename into place", final_);
  } else if (!rename_noreplace(staging_, final_)) {
    throw OutputExistsError(final_ + " appeared while the file was written; it is in " + staging_, false);
  }
  fsync_path(fs::path(final_).parent_path(), true);
  ::close(fd_);
  fd_ = -1;
}

}  // namespace losmimo::apps
