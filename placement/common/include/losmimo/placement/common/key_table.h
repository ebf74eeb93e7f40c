#pragma once
// One key table per settings struct: every INI key is declared once, with the field it sets, how
// its value is read and written, the values it accepts and a line of documentation. The table
// drives
//   known_keys()  the sections and keys IniConfig::require_known accepts,
//   load()        typed reads with their range checks; every error starts "FILE:LINE: [section]
//                 key: " (just "[section] key: " for a value given by --set),
//   check()       a validator's FieldError (field_error.h) reported as the key that set the field,
//   to_ini()      the settings as INI text, sections and keys in table order,
//   markdown()    the key reference for the docs.
// Rules that involve several fields stay in the struct's validate(), which throws FieldError;
// check() finds the key through the entries' `fields`.
//
// A table for struct S is a list of Key<S> made by the factories below, e.g.
//   using K = common::Key<GdOptions>;
//   K::real("gd", "step", &GdOptions::step, {}, "initial step, per unit gradient [m]", "0.1")
// where the field is a data member pointer or a lambda returning a reference to it, e.g.
//   [](auto& s) -> auto& { return s.cube_center_m.x(); }

#include <algorithm>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "losmimo/placement/common/field_error.h"
#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/common/range.h"

namespace losmimo::common {

enum class Kind { kDouble, kInteger, kBool, kText, kList };

// "origin:line: [section] key: <text>: must be <range>" unless range contains value.
void require_in(const Range& range, double value, const std::string& text, const std::string& where);
// Whether a failed field (FieldError::field()) is `field` or inside it ("faults" covers
// "faults[0].uav", "filter" covers "filter.noise.sigma_range_m").
bool field_covers(const std::string& field, const std::string& failed_field);

using DoubleFormat = std::string (*)(double);

template <typename S>
struct Key {
  using Read = std::function<void(S& settings, const std::string& text, const std::string& where)>;
  using Write = std::function<std::string(const S& settings, DoubleFormat format)>;

  std::string section;
  std::string key;
  Kind kind = Kind::kText;
  std::string rule;                  // the values it accepts, e.g. "integer in [1, 64]", "far_field | exact"
  std::string doc;                   // what it sets, with the unit
  std::string example;               // a valid value other than the default, as to_ini writes it (tests)
  std::vector<std::string> refused;  // values load() refuses (tests: each error names the key)
  std::vector<std::string> fields;   // the fields it sets, as FieldError::field() names them
                                     // (default: the key)
  // Parses `text` (the value as given, trimmed) into the settings. Throws InputError with the
  // whole message (`where` is "FILE:LINE: [section] key"), or std::invalid_argument, which
  // load() prefixes with "<where>: ".
  Read read;
  Write write;                            // the value as INI text
  std::function<bool(const S&)> written;  // whether to_ini writes it; empty: always
  std::function<void(S&)> if_absent;      // derives the value when the key is not given

  // Options, chained on a factory's result.
  Key sets(std::vector<std::string> set_fields) && {
    fields = std::move(set_fields);
    return std::move(*this);
  }
  Key written_if(std::function<bool(const S&)> predicate) && {
    written = std::move(predicate);
    return std::move(*this);
  }
  // to_ini writes it only when it differs from S{}'s (keeps existing INI texts unchanged).
  Key unless_default() && {
    written = [write = write](const S& s) { return write(s, &format_double) != write(S{}, &format_double); };
    return std::move(*this);
  }
  Key when_absent(std::function<void(S&)> derive) && {
    if_absent = std::move(derive);
    return std::move(*this);
  }

  // A double, parsed whole and finite, refused outside `range`.
  template <typename Field>
  static Key real(std::string section, std::string key, Field field, Range range, std::string doc,
                  std::string example) {
    auto ref = reference(field);
    return real(
        std::move(section), std::move(key), [ref](const S& s) { return ref(s); }, [ref](S& s, double v) { ref(s) = v; },
        range, std::move(doc), std::move(example));
  }
  // The same with explicit get and set (a key that sets several fields).
  template <typename Get, typename Set>
  static Key real(std::string section, std::string key, Get get, Set set, Range range, std::string doc,
                  std::string example) {
    Key k = make(std::move(section), std::move(key), Kind::kDouble, join_rule("number", range.describe()),
                 std::move(doc), std::move(example));
    k.refused = {"not-a-number"};
    for (const double v : range.outside()) k.refused.push_back(format_double(v));
    k.read = [set, range](S& s, const std::string& text, const std::string& where) {
      const double v = parse_double(text, where);
      require_in(range, v, text, where);
      set(s, v);
    };
    k.write = [get](const S& s, DoubleFormat format) { return format(get(s)); };
    return k;
  }

  // An integer in [lo, hi] (any integer field type).
  template <typename Field>
  static Key integer(std::string section, std::string key, Field field, long long lo, long long hi, std::string doc,
                     std::string example) {
    Key k =
        make(std::move(section), std::move(key), Kind::kInteger,
             "integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]", std::move(doc), std::move(example));
    k.refused = {"1.5"};
    if (lo > std::numeric_limits<long long>::min()) k.refused.push_back(std::to_string(lo - 1));
    if (hi < std::numeric_limits<long long>::max()) k.refused.push_back(std::to_string(hi + 1));
    auto ref = reference(field);
    k.read = [ref, lo, hi](S& s, const std::string& text, const std::string& where) {
      using T = std::remove_reference_t<decltype(ref(s))>;
      ref(s) = static_cast<T>(parse_integer(text, where, lo, hi));
    };
    k.write = [ref](const S& s, DoubleFormat) { return std::to_string(ref(s)); };
    return k;
  }

  // The same with the bounds as a closed Range (declared beside the struct, range.h).
  template <typename Field>
  static Key integer(std::string section, std::string key, Field field, Range range, std::string doc,
                     std::string example) {
    return integer(std::move(section), std::move(key), field, static_cast<long long>(range.lo),
                   static_cast<long long>(range.hi), std::move(doc), std::move(example));
  }

  // true/false (also 1/0, yes/no, on/off when read).
  template <typename Field>
  static Key boolean(std::string section, std::string key, Field field, std::string doc, std::string example) {
    Key k = make(std::move(section), std::move(key), Kind::kBool, "true | false", std::move(doc), std::move(example));
    k.refused = {"maybe"};
    auto ref = reference(field);
    k.read = [ref](S& s, const std::string& text, const std::string& where) { ref(s) = parse_bool(text, where); };
    k.write = [ref](const S& s, DoubleFormat) { return std::string(ref(s) ? "true" : "false"); };
    return k;
  }

  // A comma-separated list of at least one double, each in `item_range`.
  template <typename Field>
  static Key real_list(std::string section, std::string key, Field field, Range item_range, std::string doc,
                       std::string example) {
    Key k = make(std::move(section), std::move(key), Kind::kList,
                 join_rule("comma-separated numbers", item_range.describe()), std::move(doc), std::move(example));
    k.refused = {"", "0, not-a-number"};
    for (const double v : item_range.outside()) k.refused.push_back(format_double(v));
    auto ref = reference(field);
    k.read = [ref, item_range](S& s, const std::string& text, const std::string& where) {
      std::vector<double> values;
      for (const std::string& item : split_list(text)) {
        values.push_back(parse_double(item, where));
        require_in(item_range, values.back(), item, where);
        // Lists are sweep points: a repeated one would pool two points' trials into one.
        if (std::count(values.begin(), values.end(), values.back()) > 1) {
          throw InputError(where + ": '" + item + "' listed twice (each point once)");
        }
      }
      if (values.empty()) throw InputError(where + ": needs at least one value");
      ref(s) = values;
    };
    k.write = [ref](const S& s, DoubleFormat format) {
      std::string out;
      for (const double v : ref(s)) out += (out.empty() ? "" : ", ") + format(v);
      return out;
    };
    return k;
  }

  // A comma-separated list of at least one integer, each in [lo, hi].
  template <typename Field>
  static Key integer_list(std::string section, std::string key, Field field, long long lo, long long hi,
                          std::string doc, std::string example) {
    Key k = make(std::move(section), std::move(key), Kind::kList,
                 "comma-separated integers in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]", std::move(doc),
                 std::move(example));
    k.refused = {"", "0, 1.5"};
    if (lo > std::numeric_limits<long long>::min()) k.refused.push_back(std::to_string(lo - 1));
    auto ref = reference(field);
    k.read = [ref, lo, hi](S& s, const std::string& text, const std::string& where) {
      using T = typename std::remove_reference_t<decltype(ref(s))>::value_type;
      std::remove_reference_t<decltype(ref(s))> values;
      for (const std::string& item : split_list(text)) {
        values.push_back(static_cast<T>(parse_integer(item, where, lo, hi)));
        if (std::count(values.begin(), values.end(), values.back()) > 1) {
          throw InputError(where + ": '" + item + "' listed twice (each point once)");
        }
      }
      if (values.empty()) throw InputError(where + ": needs at least one value");
      ref(s) = values;
    };
    k.write = [ref](const S& s, DoubleFormat) {
      std::string out;
      for (const auto v : ref(s)) out += (out.empty() ? "" : ", ") + std::to_string(v);
      return out;
    };
    return k;
  }

  // Any other value (names, structured lists): `read` parses, `write` prints.
  static Key text(std::string section, std::string key, Read read, std::function<std::string(const S&)> write,
                  std::string rule, std::string doc, std::string example) {
    Key k = make(std::move(section), std::move(key), Kind::kText, std::move(rule), std::move(doc), std::move(example));
    k.refused = {"not-a-value"};
    k.read = std::move(read);
    k.write = [write = std::move(write)](const S& s, DoubleFormat) { return write(s); };
    return k;
  }

 private:
  static Key make(std::string section, std::string key, Kind kind, std::string rule, std::string doc,
                  std::string example) {
    Key k;
    k.fields = {key};  // by default the key is the field's name
    k.section = std::move(section);
    k.key = std::move(key);
    k.kind = kind;
    k.rule = std::move(rule);
    k.doc = std::move(doc);
    k.example = std::move(example);
    return k;
  }
  static std::string join_rule(const std::string& what, const std::string& range) {
    return range.empty() ? what : what + " " + range;
  }
  // A data member pointer as a lambda returning a reference, like the lambdas one may pass.
  template <typename Field>
  static auto reference(Field field) {
    if constexpr (std::is_member_object_pointer_v<Field>) {
      return [field](auto& s) -> auto& { return s.*field; };
    } else {
      return field;
    }
  }
};

// The keys of a member struct as keys of the enclosing one; their fields become
// "<member_name>.<field>".
template <typename Outer, typename Inner>
Key<Outer> nested(const Key<Inner>& inner, Inner Outer::*member, const std::string& member_name) {
  Key<Outer> k;
  k.section = inner.section;
  k.key = inner.key;
  k.kind = inner.kind;
  k.rule = inner.rule;
  k.doc = inner.doc;
  k.example = inner.example;
  k.refused = inner.refused;
  for (const std::string& f : inner.fields) k.fields.push_back(member_name + "." + f);
  k.read = [read = inner.read, member](Outer& s, const std::string& text, const std::string& where) {
    read(s.*member, text, where);
  };
  k.write = [write = inner.write, member](const Outer& s, DoubleFormat format) { return write(s.*member, format); };
  if (inner.written) k.written = [written = inner.written, member](const Outer& s) { return written(s.*member); };
  if (inner.if_absent) k.if_absent = [derive = inner.if_absent, member](Outer& s) { derive(s.*member); };
  return k;
}

template <typename Outer, typename Inner>
std::vector<Key<Outer>> nested(const std::vector<Key<Inner>>& inner, Inner Outer::*member,
                               const std::string& member_name) {
  std::vector<Key<Outer>> keys;
  for (const Key<Inner>& k : inner) keys.push_back(nested(k, member, member_name));
  return keys;
}

// Thrown by KeyTable's constructor for a table that cannot work (a programming error).
void require_valid_table(const std::vector<std::pair<std::string, std::string>>& section_keys);

template <typename S>
class KeyTable {
 public:
  // `format`: how to_ini writes doubles (default: the shortest text that reads back exactly).
  // The keys of a section must be consecutive; a key may appear once.
  explicit KeyTable(std::vector<Key<S>> keys, DoubleFormat format = &format_double)
      : keys_(std::move(keys)), format_(format) {
    std::vector<std::pair<std::string, std::string>> names;
    for (const Key<S>& k : keys_) names.emplace_back(k.section, k.key);
    require_valid_table(names);
  }

  // An old spelling: known (so that require_known passes it), refused by load() with a message
  // naming the key to use.
  KeyTable& renamed(std::string section, std::string key, std::string new_section, std::string new_key) {
    renamed_.push_back({std::move(section), std::move(key), std::move(new_section), std::move(new_key)});
    return *this;
  }

  const std::vector<Key<S>>& keys() const { return keys_; }
  // The entry of [section] key; throws std::out_of_range if the table has none.
  const Key<S>& key(const std::string& section, const std::string& key) const {
    for (const Key<S>& k : keys_) {
      if (k.section == section && k.key == key) return k;
    }
    throw std::out_of_range("no key [" + section + "] " + key + " in the table");
  }

  std::map<std::string, std::set<std::string>> known_keys() const {
    std::map<std::string, std::set<std::string>> known;
    for (const Key<S>& k : keys_) known[k.section].insert(k.key);
    for (const Renamed& r : renamed_) known[r.section].insert(r.key);
    return known;
  }

  // Reads every key the config has, in table order (a key absent keeps the settings' value, or
  // runs its if_absent); throws InputError naming the key and value.
  void load(const IniConfig& config, S& settings) const {
    for (const Renamed& r : renamed_) {
      if (config.has(r.section, r.key)) {
        throw InputError(config.where(r.section, r.key) + ": no longer read: set [" + r.new_section + "] " + r.new_key +
                         " instead");
      }
    }
    for (const Key<S>& k : keys_) {
      if (!config.has(k.section, k.key)) {
        if (k.if_absent) k.if_absent(settings);
        continue;
      }
      const std::string where = config.where(k.section, k.key);
      try {
        k.read(settings, config.get_string(k.section, k.key, ""), where);
      } catch (const std::invalid_argument& e) {
        throw InputError(where + ": " + e.what());
      }
    }
  }

  // Runs validate(); a FieldError from it becomes an InputError "<where the key is>: <message>",
  // where the key is the first entry whose fields cover `member` + "." + the failed field;
  // another std::invalid_argument becomes "config: <message>".
  template <typename Fn>
  void check(const IniConfig& config, const std::string& member, Fn&& validate) const {
    try {
      validate();
    } catch (const FieldError& e) {
      throw InputError(where(config, member.empty() ? e.field() : member + "." + e.field()) + ": " + e.what());
    } catch (const std::invalid_argument& e) {
      throw InputError("config: " + std::string(e.what()));
    }
  }

  // "FILE:LINE: [section] key" of the key that sets `field` ("[section] key" when the config
  // does not give it), or "config" when no key sets it.
  std::string where(const IniConfig& config, const std::string& field) const {
    for (const Key<S>& k : keys_) {
      for (const std::string& f : k.fields) {
        if (field_covers(f, field)) return config.where(k.section, k.key);
      }
    }
    return "config";
  }

  // "[section]\nkey = value\n..." for every key written, a blank line between sections.
  std::string to_ini(const S& settings) const {
    std::string out;
    const std::string* section = nullptr;
    for (const Key<S>& k : keys_) {
      if (k.written && !k.written(settings)) continue;
      if (!section || *section != k.section) {
        out += (out.empty() ? "[" : "\n[") + k.section + "]\n";
        section = &k.section;
      }
      out += k.key + " = " + k.write(settings, format_) + "\n";
    }
    return out;
  }

  // "| [section] | key | default | values | meaning |" rows, one per key of `sections` (all when
  // empty), defaults from S{}.
  std::string markdown(const std::set<std::string>& sections = {}) const {
    std::string out = "| section | key | default | values | meaning |\n|---|---|---|---|---|\n";
    // On the heap: GCC 12 at -O3 takes the inlined default members of a large S for
    // maybe-uninitialised on the stack.
    const auto defaults = std::make_unique<const S>();
    // A '|' inside a cell (rules such as "true | false") would end the cell: escaped.
    const auto cell = [](const std::string& text) {
      std::string escaped;
      for (const char c : text) escaped += c == '|' ? std::string("\\|") : std::string(1, c);
      return escaped;
    };
    for (const Key<S>& k : keys_) {
      if (!sections.empty() && sections.count(k.section) == 0) continue;
      out += "| [" + k.section + "] | " + k.key + " | " + cell(k.write(*defaults, &format_double)) + " | " +
             cell(k.rule) + " | " + cell(k.doc) + " |\n";
    }
    return out;
  }

  // Sets every key to_ini writes into `config` (the others keep what it had).
  void write_to(IniConfig& config, const S& settings) const {
    for (const Key<S>& k : keys_) {
      if (!k.written || k.written(settings)) config.set(k.section, k.key, k.write(settings, format_));
    }
  }

 private:
  struct Renamed {
    std::string section, key, new_section, new_key;
  };
  std::vector<Key<S>> keys_;
  DoubleFormat format_;
  std::vector<Renamed> renamed_;
};

}  // namespace losmimo::common
