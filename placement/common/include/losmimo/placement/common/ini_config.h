#pragma once
// A strict INI reader in MRPT's style: `[section]` headers, `key = value` lines, `#`, `;` or `//`
// comments (whole line or after the value; `//` right after ':' is a URL's, not a comment, as
// MRPT reads it), case-sensitive names, a leading UTF-8 byte-order
// mark ignored; files of at most kMaxConfigBytes (bounded_read.h). Strict where MRPT's
// CConfigFile is lenient: a missing file, a malformed line, a duplicate key and (with
// require_known) an unknown section or key are errors naming the file, line and key.
// (Written here because placement may not depend on MRPT; mrpt::config is the library
// counterpart.)

#include <map>
#include <set>
#include <string>
#include <vector>

#include "losmimo/placement/common/input_error.h"

namespace losmimo::common {

// Splits a comma-separated value into its items, each trimmed of spaces and tabs.
std::vector<std::string> split_list(const std::string& text);

class IniConfig {
 public:
  IniConfig() = default;
  static IniConfig from_file(const std::string& path);
  static IniConfig from_string(const std::string& text, const std::string& origin = "<string>");

  // Applies an override "section.key=value" (as from --set); throws InputError if malformed.
  void set_override(const std::string& assignment);
  // `origin` names where the value came from in messages (an option such as "--trials").
  void set(const std::string& section, const std::string& key, const std::string& value,
           const std::string& origin = "--set");

  bool has(const std::string& section, const std::string& key) const;
  bool has_section(const std::string& section) const;
  // The given sections only (entries keep their origin and line, for messages).
  IniConfig subset(const std::set<std::string>& sections) const;
  // Typed getters: the fallback when absent, else the parsed value or an InputError naming
  // "origin:line: [section] key".
  double get_double(const std::string& section, const std::string& key, double fallback) const;
  long long get_integer(const std::string& section, const std::string& key, long long fallback, long long lo,
                        long long hi) const;
  bool get_bool(const std::string& section, const std::string& key, bool fallback) const;
  std::string get_string(const std::string& section, const std::string& key, const std::string& fallback) const;
  // "origin:line: [section] key" for messages about a key's value.
  std::string where(const std::string& section, const std::string& key) const;

  // Throws InputError on the first section or key not in `known`.
  void require_known(const std::map<std::string, std::set<std::string>>& known) const;

  // Serialises back to INI text (sections and keys sorted), e.g. to log the config used.
  std::string to_string() const;

 private:
  struct Entry {
    std::string value;
    std::string origin;
    int line = 0;  // 0: set by an override
  };
  std::map<std::string, std::map<std::string, Entry>> sections_;
};

}  // namespace losmimo::common
