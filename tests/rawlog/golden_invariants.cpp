#include "rawlog/golden_invariants.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include <Eigen/Cholesky>

#include "support/shape_nees.h"

namespace losmimo::rawlog::golden {

const std::vector<std::string>& variant_keys() {
  static const std::vector<std::string> keys = {"status",
                                                "epochs",
                                                "final_icn_min",
                                                "final_icn_max",
                                                "nees_epoch_low",
                                                "nees_epoch_high",
                                                "nees_epoch_min_fraction",
                                                "nees_mean_low",
                                                "nees_mean_high",
                                                "shape_nees_mean_low",
                                                "shape_nees_mean_high",
                                                "range_rmse_min_m",
                                                "rmse_max_m",
                                                "beacons",
                                                "fallback_fraction_min",
                                                "fallback_fraction_max"};
  return keys;
}

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');)
    if (!trim(item).empty()) out.push_back(trim(item));
  return out;
}

}  // namespace

InvariantsFile read_invariants(const std::string& path) {
  InvariantsFile f;
  f.path = path;
  std::ifstream in(path);
  if (!in) {
    f.problems.push_back(path + ": cannot be read");
    return f;
  }
  std::string section, reason;
  int n = 0;
  for (std::string raw; std::getline(in, raw);) {
    ++n;
    const std::string line = trim(raw);
    const std::string where = path + ":" + std::to_string(n);
    if (line.empty()) {
      reason.clear();  // a reason belongs to the key right below it
    } else if (line[0] == '#') {
      reason += (reason.empty() ? "" : " ") + trim(line.substr(1));
    } else if (line.front() == '[' && line.back() == ']') {
      section = trim(line.substr(1, line.size() - 2));
      f.sections[section];
      reason.clear();
    } else if (const auto eq = line.find('='); eq != std::string::npos && !section.empty()) {
      const std::string key = trim(line.substr(0, eq));
      if (reason.empty()) f.problems.push_back(where + ": " + key + " has no reason (a comment line right above it)");
      if (!f.sections[section].emplace(key, Bound{trim(line.substr(eq + 1)), reason, n}).second)
        f.problems.push_back(where + ": " + key + " given twice in [" + section + "]");
      reason.clear();
    } else {
      f.problems.push_back(where + ": not a [section], # comment or key = value in a section: " + line);
    }
  }
  return f;
}

std::vector<std::string> listed_variants(const InvariantsFile& f) {
  const auto m = f.sections.find("mission");
  if (m == f.sections.end() || !m->second.count("variants")) return {};
  return split_list(m->second.at("variants").value);
}

// [mission]'s bounds with [variant]'s on top.
Bounds bounds_of(const InvariantsFile& f, const std::string& variant) {
  Bounds b;
  if (const auto m = f.sections.find("mission"); m != f.sections.end()) b = m->second;
  b.erase("variants");
  if (const auto v = f.sections.find(variant); v != f.sections.end())
    for (const auto& [key, bound] : v->second) b[key] = bound;
  return b;
}

ReplayFigures figures_of(const MissionLog& log, const ReplayResult& r) {
  ReplayFigures f;
  f.status = log.run_end.status;
  f.epochs = static_cast<int>(log.epochs.size());
  f.uavs = log.num_uavs;
  f.final_icn = r.final_icn;
  f.epoch_average_nees.assign(f.epochs, 0.0);
  f.epoch_nees_samples.assign(f.epochs, 0);
  double nees_sum = 0.0, x_sq = 0.0, sq = 0.0;
  int nees_n = 0;
  for (const ReplayUavEpoch& e : r.estimates) {
    if (e.has_beacon) ++f.beacons;
    if (!e.has_truth) continue;
    const Eigen::Vector3d err_m = e.belief.mean_m - e.truth_m;
    const double nees = err_m.dot(e.belief.cov_m2.ldlt().solve(err_m));
    f.epoch_average_nees[e.epoch] += nees;
    ++f.epoch_nees_samples[e.epoch];
    nees_sum += nees;
    ++nees_n;
    if (e.has_beacon) {
      x_sq += err_m.x() * err_m.x();
      sq += err_m.squaredNorm();
    }
  }
  for (int k = 0; k < f.epochs; ++k)
    if (f.epoch_nees_samples[k] > 0) f.epoch_average_nees[k] /= f.epoch_nees_samples[k];
  // The shape NEES per degree of freedom of each epoch with every UAV's truth, by the
  // pseudo-inverse (support/shape_nees.h), not by the library's QR form.
  std::vector<Eigen::Matrix3Xd> truth(f.epochs, Eigen::Matrix3Xd::Zero(3, f.uavs)), mean = truth;
  std::vector<std::vector<Eigen::Matrix2d>> cov(f.epochs, std::vector<Eigen::Matrix2d>(f.uavs));
  for (const ReplayUavEpoch& e : r.estimates) {
    if (!e.has_truth || e.epoch >= f.epochs || e.uav >= f.uavs) continue;
    truth[e.epoch].col(e.uav) = e.truth_m;
    mean[e.epoch].col(e.uav) = e.belief.mean_m;
    cov[e.epoch][e.uav] = e.belief.cov_m2.bottomRightCorner<2, 2>();
  }
  double shape_sum = 0.0;
  int shape_n = 0;
  for (int k = 0; k < f.epochs; ++k) {
    if (f.epoch_nees_samples[k] != f.uavs) continue;
    shape_sum += test_support::shape_nees_by_pseudo_inverse(truth[k], mean[k], cov[k]);
    ++shape_n;
  }
  f.shape_nees = shape_n > 0 ? shape_sum / shape_n : std::nan("");
  f.average_nees = nees_n > 0 ? nees_sum / nees_n : std::nan("");
  f.range_rmse_m = f.beacons > 0 ? std::sqrt(x_sq / f.beacons) : std::nan("");
  f.rmse_m = f.beacons > 0 ? std::sqrt(sq / f.beacons) : std::nan("");
  f.fallback_fraction = static_cast<double>(r.fallback_uav_epochs) / (static_cast<double>(f.epochs) * f.uavs);
  return f;
}

// ---------------------------------------------------------------------------------------------
// The checker.

namespace {

std::string fmt(double v) {
  std::ostringstream o;
  o.precision(10);
  o << v;
  return o.str();
}

// Collects one message per violated bound: the key, the file's value, what is wrong and the
// bound's reason.
class Checker {
 public:
  explicit Checker(const Bounds& bounds) : bounds_(bounds) {}

  void fail(const std::string& key, const std::string& what) {
    const auto it = bounds_.find(key);
    out_.push_back(key + " = " + (it == bounds_.end() ? "?" : it->second.value) + ": " + what +
                   (it == bounds_.end() ? "" : "  [reason: " + it->second.reason + "]"));
  }
  // The bound as a finite number into v; false (and a message) if missing or not one.
  bool number(const std::string& key, double& v) {
    const auto it = bounds_.find(key);
    if (it == bounds_.end()) {
      fail(key, "missing");
      return false;
    }
    char* end = nullptr;
    v = std::strtod(it->second.value.c_str(), &end);
    if (it->second.value.empty() || *end != '\0' || !std::isfinite(v)) {
      fail(key, "not a finite number");
      return false;
    }
    return true;
  }
  void at_least(const std::string& key, double value, const std::string& what) {
    double b = 0.0;
    if (number(key, b) && !(value >= b)) fail(key, what + " " + fmt(value) + " is below it");
  }
  void at_most(const std::string& key, double value, const std::string& what) {
    double b = 0.0;
    if (number(key, b) && !(value <= b)) fail(key, what + " " + fmt(value) + " is above it");
  }
  void exactly(const std::string& key, double value, const std::string& what) {
    double b = 0.0;
    if (number(key, b) && value != b) fail(key, what + " is " + fmt(value));
  }
  std::vector<std::string>& messages() { return out_; }

 private:
  const Bounds& bounds_;
  std::vector<std::string> out_;
};

// Per-epoch NEES: the fraction of the epochs (every UAV with truth) inside the band.
void check_epoch_nees(Checker& c, const ReplayFigures& f) {
  double low = 0.0, high = 0.0, min_fraction = 0.0;
  if (!c.number("nees_epoch_low", low) || !c.number("nees_epoch_high", high) ||
      !c.number("nees_epoch_min_fraction", min_fraction)) {
    return;
  }
  int inside = 0;
  std::string outside;
  for (int k = 0; k < f.epochs; ++k) {
    const double v = f.epoch_average_nees[k];
    if (f.epoch_nees_samples[k] != f.uavs) {
      c.fail("nees_epoch_low", "epoch " + std::to_string(k) + " has " + std::to_string(f.epoch_nees_samples[k]) +
                                   " UAVs with truth; the band is stated for " + std::to_string(f.uavs));
    } else if (v >= low && v <= high) {
      ++inside;
    } else if (outside.size() < 200) {
      outside += " " + std::to_string(k) + ":" + fmt(v);
    }
  }
  const double fraction = f.epochs > 0 ? static_cast<double>(inside) / f.epochs : 0.0;
  if (!(fraction >= min_fraction))
    c.fail("nees_epoch_min_fraction", std::to_string(inside) + " of " + std::to_string(f.epochs) + " epochs inside [" +
                                          fmt(low) + ", " + fmt(high) + "]; outside (epoch:NEES):" + outside);
}

}  // namespace

std::vector<std::string> violations(const Bounds& bounds, const ReplayFigures& f) {
  Checker c(bounds);
  const std::set<std::string> known(variant_keys().begin(), variant_keys().end());
  for (const auto& [key, b] : bounds)
    if (!known.count(key)) c.messages().push_back("unknown key " + key + " (line " + std::to_string(b.line) + ")");
  if (const auto it = bounds.find("status"); it == bounds.end())
    c.fail("status", "missing");
  else if (it->second.value != f.status)
    c.fail("status", "the log's END_OF_LOG status is '" + f.status + "'");
  c.exactly("epochs", f.epochs, "the log's epoch count");
  c.at_least("final_icn_min", f.final_icn, "final ICN");
  c.at_most("final_icn_max", f.final_icn, "final ICN");
  check_epoch_nees(c, f);
  c.at_least("nees_mean_low", f.average_nees, "average NEES");
  c.at_most("nees_mean_high", f.average_nees, "average NEES");
  c.at_least("shape_nees_mean_low", f.shape_nees, "average shape NEES per degree of freedom");
  c.at_most("shape_nees_mean_high", f.shape_nees, "average shape NEES per degree of freedom");
  c.at_least("range_rmse_min_m", f.range_rmse_m, "line-of-sight RMSE over the beacon epochs");
  c.at_most("rmse_max_m", f.rmse_m, "3-D RMSE over the beacon epochs");
  c.exactly("beacons", f.beacons, "beacons consumed");
  c.at_least("fallback_fraction_min", f.fallback_fraction, "fallback fraction");
  c.at_most("fallback_fraction_max", f.fallback_fraction, "fallback fraction");
  return c.messages();
}

std::string joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += "\n  " + l;
  return s;
}

ReplayOptions options_of(const std::string& variant) {
  ReplayOptions o;
  o.estimator = localization::filter_kind_from_string(variant.substr(0, variant.find('+')));
  o.refine = variant.find("+ceres") != std::string::npos;
  return o;
}

const std::vector<std::string>& shipped_missions() {
  static const std::vector<std::string> m = {"beacon_outage", "high_beacon_noise", "nominal"};
  return m;
}

}  // namespace losmimo::rawlog::golden
