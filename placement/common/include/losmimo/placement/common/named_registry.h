#pragma once
// Named entries in registration order: what the planner registry (placement/planner_registry.h)
// and the estimator registry (fusion/coevaluation/estimator_registry.h) share. An entry type has
// a `std::string name`; names are [a-z0-9_]+ and unique. Not thread-safe against concurrent
// lookups: entries are added before any run starts.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "losmimo/placement/common/text.h"

namespace losmimo::common {

template <typename Entry>
class NamedRegistry {
 public:
  // `kind` names an entry in messages ("planner", "estimator").
  NamedRegistry(std::string kind, std::vector<Entry> builtins) : kind_(std::move(kind)) {
    for (Entry& e : builtins) add(std::move(e));
  }

  // std::invalid_argument for a badly spelled or taken name.
  void add(Entry entry) {
    const bool spelled = !entry.name.empty() && std::all_of(entry.name.begin(), entry.name.end(), [](char c) {
      return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
    });
    if (!spelled) throw std::invalid_argument("register_" + kind_ + ": '" + entry.name + "': a name is [a-z0-9_]+");
    if (find(entry.name))
      throw std::invalid_argument("register_" + kind_ + ": '" + entry.name + "' is registered already");
    entries_.push_back(std::move(entry));
  }
  // nullptr when absent.
  const Entry* find(const std::string& name) const {
    for (const Entry& e : entries_) {
      if (e.name == name) return &e;
    }
    return nullptr;
  }
  // std::invalid_argument naming the known entries when absent.
  const Entry& at(const std::string& name) const {
    if (const Entry* e = find(name)) return *e;
    throw std::invalid_argument("unknown " + kind_ + " '" + name + "' (known: " + join(names()) + ")");
  }
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const Entry& e : entries_) out.push_back(e.name);
    return out;
  }

 private:
  std::string kind_;
  std::vector<Entry> entries_;
};

}  // namespace losmimo::common
