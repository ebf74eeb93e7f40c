#include "losmimo/placement/common/ini_config.h"

#include "losmimo/placement/common/text.h"

#include <cctype>
#include <fstream>
#include <sstream>
#include <string_view>

#include "losmimo/placement/common/bounded_read.h"

namespace losmimo::common {

namespace {
// The field an error about a key names: "[section] key".
std::string field_name(const std::string& section, const std::string& key) { return "[" + section + "] " + key; }

bool valid_name(const std::string& name) {
  if (name.empty()) return false;
  for (const char c : name) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return false;
  }
  return true;
}

// `#` and `;` start a comment anywhere; `//` too, as in MRPT's files ("key = value // why"),
// except right after a ':' (a URL's "http://" is a value, as MRPT reads it).
std::string strip_comment(const std::string& line) {
  std::size_t pos = line.find_first_of("#;");
  for (std::size_t s = line.find("//"); s != std::string::npos && s < pos; s = line.find("//", s + 1)) {
    if (s == 0 || line[s - 1] != ':') {
      pos = s;
      break;
    }
  }
  return pos == std::string::npos ? line : line.substr(0, pos);
}
}  // namespace

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const std::size_t b = item.find_first_not_of(" \t");
    const std::size_t e = item.find_last_not_of(" \t");
    items.push_back(b == std::string::npos ? std::string() : item.substr(b, e - b + 1));
  }
  return items;
}

IniConfig IniConfig::from_file(const std::string& path) {
  // Bounded: a config is a few KB; /dev/zero or a huge file is refused, not slurped.
  return from_string(read_file_bounded(path, kMaxConfigBytes, "config file"), path);
}

IniConfig IniConfig::from_string(const std::string& text, const std::string& origin) {
  IniConfig cfg;
  // A UTF-8 byte-order mark (written by some editors) is not part of the first line.
  constexpr std::string_view kBom = "\xEF\xBB\xBF";
  std::istringstream in(text.compare(0, kBom.size(), kBom) == 0 ? text.substr(kBom.size()) : text);
  std::string raw;
  std::string section;
  int line_no = 0;
  while (std::getline(in, raw)) {
    ++line_no;
    const std::string where = origin + ":" + std::to_string(line_no);
    if (raw.find('\0') != std::string::npos) throw InputError(where + ": NUL byte in config");
    const std::string line = trim(strip_comment(raw));
    if (line.empty()) continue;
    if (line.front() == '[') {
      if (line.back() != ']') throw InputError(where + ": malformed section header '" + line + "'");
      section = trim(line.substr(1, line.size() - 2));
      if (!valid_name(section)) throw InputError(where + ": bad section name '" + section + "'");
      cfg.sections_[section];
      continue;
    }
    const std::size_t eq = line.find('=');
    if (eq == std::string::npos) throw InputError(where + ": expected 'key = value', got '" + line + "'");
    if (section.empty()) throw InputError(where + ": key outside any [section]: '" + line + "'");
    const std::string key = trim(line.substr(0, eq));
    if (!valid_name(key)) throw InputError(where + ": bad key name '" + key + "'");
    auto& keys = cfg.sections_[section];
    if (keys.count(key)) {
      throw InputError(where + ": duplicate key [" + section + "] " + key + " (first at line " +
                       std::to_string(keys[key].line) + ")");
    }
    keys[key] = Entry{trim(line.substr(eq + 1)), origin, line_no};
  }
  return cfg;
}

void IniConfig::set_override(const std::string& assignment) {
  const std::size_t eq = assignment.find('=');
  const std::size_t dot = assignment.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot > eq) {
    throw InputError("--set '" + assignment + "': expected section.key=value");
  }
  const std::string section = trim(assignment.substr(0, dot));
  const std::string key = trim(assignment.substr(dot + 1, eq - dot - 1));
  if (!valid_name(section) || !valid_name(key)) {
    throw InputError("--set '" + assignment + "': bad section or key name");
  }
  set(section, key, trim(assignment.substr(eq + 1)));
}

void IniConfig::set(const std::string& section, const std::string& key, const std::string& value,
                    const std::string& origin) {
  sections_[section][key] = Entry{value, origin, 0};
}

bool IniConfig::has(const std::string& section, const std::string& key) const {
  const auto s = sections_.find(section);
  return s != sections_.end() && s->second.count(key) > 0;
}

bool IniConfig::has_section(const std::string& section) const { return sections_.count(section) > 0; }

IniConfig IniConfig::subset(const std::set<std::string>& sections) const {
  IniConfig out;
  for (const auto& [name, keys] : sections_) {
    if (sections.count(name)) out.sections_[name] = keys;
  }
  return out;
}

std::string IniConfig::where(const std::string& section, const std::string& key) const {
  const auto s = sections_.find(section);
  if (s != sections_.end()) {
    const auto k = s->second.find(key);
    if (k != s->second.end()) {
      const Entry& e = k->second;
      const std::string at = e.line > 0 ? e.origin + ":" + std::to_string(e.line) : e.origin;
      return at + ": [" + section + "] " + key;
    }
  }
  return "[" + section + "] " + key;
}

double IniConfig::get_double(const std::string& section, const std::string& key, double fallback) const {
  return has(section, key)
             ? parse_double(sections_.at(section).at(key).value, where(section, key), field_name(section, key))
             : fallback;
}

long long IniConfig::get_integer(const std::string& section, const std::string& key, long long fallback, long long lo,
                                 long long hi) const {
  return has(section, key)
             ? parse_integer(sections_.at(section).at(key).value, where(section, key), lo, hi, field_name(section, key))
             : fallback;
}

bool IniConfig::get_bool(const std::string& section, const std::string& key, bool fallback) const {
  return has(section, key)
             ? parse_bool(sections_.at(section).at(key).value, where(section, key), field_name(section, key))
             : fallback;
}

std::string IniConfig::get_string(const std::string& section, const std::string& key,
                                  const std::string& fallback) const {
  return has(section, key) ? sections_.at(section).at(key).value : fallback;
}

void IniConfig::require_known(const std::map<std::string, std::set<std::string>>& known) const {
  for (const auto& [section, keys] : sections_) {
    const auto k = known.find(section);
    if (k == known.end()) {
      std::string where_first = keys.empty() ? "" : where(section, keys.begin()->first) + ": ";
      throw InputError(where_first + "unknown section [" + section + "]", "[" + section + "]");
    }
    for (const auto& [key, entry] : keys) {
      if (!k->second.count(key)) throw InputError(where(section, key) + ": unknown key", field_name(section, key));
    }
  }
}

std::string IniConfig::to_string() const {
  std::ostringstream out;
  for (const auto& [section, keys] : sections_) {
    if (out.tellp() > 0) out << "\n";
    out << "[" << section << "]\n";
    for (const auto& [key, entry] : keys) out << key << " = " << entry.value << "\n";
  }
  return out.str();
}

}  // namespace losmimo::common
