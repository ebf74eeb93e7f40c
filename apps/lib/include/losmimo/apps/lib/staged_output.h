#pragma once
// Outputs that are complete or absent: an output folder holds one run or nothing mixed, an
// output file is a whole one or none.
//
// StagedDir: an app writes every output into the staging folder `<final>.partial/` beside the
// final one. publish() lists every file in the manifest `losmimo-run.ini` (written last:
// [run] kind and the app's keys, [files] each file's size and FNV-1a digest), fsyncs every file
// and the folder, and renames the folder into place in one step (renameat2: RENAME_NOREPLACE
// into an absent path; RENAME_EXCHANGE over an empty folder or, with `replace`, over an earlier
// run, which is then removed). An interrupted run leaves only `<final>.partial/`; the final
// folder is never half-written. The staging folder is locked (flock) while a process uses it.
//
// Before any work, create() looks at what is there (inspect_output):
//   absent, or an empty folder                      the run goes ahead
//   a losmimo output: a folder with a manifest and nothing it does not list, a folder of files
//   only losmimo writes (written before manifests), or (StagedFile) a file
//                                                   OutputExistsError naming it, unless replace
//   anything else (a folder with other files)       OutputExistsError even with replace: never
//                                                   deleted
// and at `<final>.partial`: in use by a running process -> OutputExistsError; an interrupted
// run -> OutputExistsError (StaleStaging::kRefuse: it can be resumed) unless replace, or
// removed (kDiscard).
//
// StagedFile: the same for one file, staged as `<final>.partial` (kept on interruption: a
// readable prefix, never under the final name).

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/common/input_error.h"

namespace losmimo::apps {

inline constexpr const char* kManifestName = "losmimo-run.ini";
inline constexpr const char* kStagingSuffix = ".partial";

// A run's output is in the way; replaceable(): `replace` would replace it whole.
class OutputExistsError : public common::InputError {
 public:
  OutputExistsError(const std::string& message, bool replaceable, std::string resume_dir = {})
      : common::InputError(message), replaceable_(replaceable), resume_dir_(std::move(resume_dir)) {}
  bool replaceable() const { return replaceable_; }
  // The folder an interrupted run there continues into with --resume; empty when none does.
  const std::string& resume_dir() const { return resume_dir_; }

 private:
  bool replaceable_;
  std::string resume_dir_;
};

struct ExistingOutput {
  enum Kind { kAbsent, kEmptyFolder, kOurs, kNotOurs };
  Kind kind = kAbsent;
  std::string description;  // "a finished experiment (losmimo-run.ini, 12 files)", ...
};
// What is at `path` (a folder output).
ExistingOutput inspect_output(const std::filesystem::path& path);

// The manifest's content besides [files]: [run] kind = <kind>, then run_keys in order, then
// extra_sections (INI text, e.g. "[shard]\nindex = 0\n").
struct Manifest {
  std::string kind;
  std::vector<std::pair<std::string, std::string>> run_keys;
  std::string extra_sections;
};
// Reads DIR/losmimo-run.ini (strict INI, bounded); InputError naming it if missing or malformed.
common::IniConfig read_manifest(const std::filesystem::path& dir);
// Checks that every file the manifest lists is there with its size and digest; InputError
// naming the folder and the first file that differs.
void verify_manifest_files(const std::filesystem::path& dir, const common::IniConfig& manifest);

enum class StaleStaging { kRefuse, kDiscard };

class StagedDir {
 public:
  // Checks the final folder and its staging folder (above), then creates and locks a fresh
  // staging folder. Throws OutputExistsError or InputError (a path that cannot be a run folder).
  static StagedDir create(const std::string& final_dir, bool replace, StaleStaging stale);
  // The checks of create() alone: nothing is created or removed.
  static void check(const std::string& final_dir, bool replace, StaleStaging stale);
  // Locks the staging folder of an interrupted run into final_dir, as it is. InputError if there
  // is none or it is in use.
  static StagedDir resume(const std::string& final_dir, bool replace);
  // The staging folder of final_dir (whether or not it exists).
  static std::filesystem::path staging_path_of(const std::string& final_dir);

  StagedDir(StagedDir&& other) noexcept;
  StagedDir& operator=(StagedDir&&) = delete;
  ~StagedDir();  // unlocks; an unpublished staging folder stays (an interrupted run)

  const std::filesystem::path& path() const { return staging_; }  // write the outputs here
  const std::filesystem::path& final_path() const { return final_; }

  // Writes the manifest, fsyncs and renames the folder into place. Throws OutputExistsError if
  // the final path was taken meanwhile (the outputs then stay in path()), std::runtime_error on
  // an I/O failure.
  void publish(const Manifest& manifest);

 private:
  StagedDir(std::filesystem::path final_dir, std::filesystem::path staging, int lock_fd, bool replace);
  std::filesystem::path final_;
  std::filesystem::path staging_;
  int lock_fd_ = -1;
  bool replace_ = false;
};

class StagedFile {
 public:
  // Checks the final path (absent, or a file and `replace`), then creates, locks and empties
  // `<final>.partial`.
  static StagedFile create(const std::string& final_path, bool replace);
  StagedFile(StagedFile&& other) noexcept;
  StagedFile& operator=(StagedFile&&) = delete;
  ~StagedFile();

  const std::string& path() const { return staging_; }  // write here
  const std::string& final_path() const { return final_; }
  // fsyncs the file and renames it into place (replacing the old one only with `replace`).
  void publish();

 private:
  StagedFile(std::string final_path, std::string staging, int fd, bool replace);
  std::string final_;
  std::string staging_;
  int fd_ = -1;
  bool replace_ = false;
};

}  // namespace losmimo::apps
