#pragma once
// A metric's handle and an extension's metric values in one record (metrics.h declares the
// tables these refer to).
//   MetricId      the column name a metric table declares. Reports look metrics up by handle
//                 (SummaryRow::metric), never by a string literal: a misspelt handle does not
//                 compile.
//   MetricValues  an extension's values in one record, set by handle. Every metric of the
//                 extension's table must be set, NaN where it does not apply: "unset" is not NaN,
//                 and the engine refuses a record that leaves one unset (extension_columns).

#include <cstring>
#include <optional>
#include <utility>
#include <vector>

namespace losmimo::experiment {

struct MetricId {
  const char* name;
};
inline bool operator==(MetricId a, MetricId b) { return std::strcmp(a.name, b.name) == 0; }
inline bool operator!=(MetricId a, MetricId b) { return !(a == b); }

class MetricValues {
 public:
  // Sets (or replaces) the value of `id`; NaN is a value.
  void set(MetricId id, double value);
  // The value of `id`, nullopt while unset.
  std::optional<double> find(MetricId id) const;
  // The value of `id`; std::out_of_range naming it while unset.
  double at(MetricId id) const;
  // The metrics set, in the order they were first set.
  const std::vector<std::pair<MetricId, double>>& entries() const { return values_; }
  bool empty() const { return values_.empty(); }

 private:
  std::vector<std::pair<MetricId, double>> values_;
};

}  // namespace losmimo::experiment
