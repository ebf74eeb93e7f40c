#include "losmimo/placement/swarm_channel.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <string>

#include "finite.h"

namespace losmimo::placement {

namespace {
// Rank-one updates drift by ~1e-16 relative each; a periodic exact rebuild bounds it.
constexpr int kRefreshEvery = 256;

// Lane p of (px, py, pz) gets column offset + p of q_m, clamped to its columns: lanes past the
// last column repeat it, lanes before the first repeat the first (zeros without columns).
void positions_into_lanes(const Eigen::Ref<const Eigen::Matrix3Xd>& q_m, int offset, double* px, double* py,
                          double* pz) {
  const int cols = static_cast<int>(q_m.cols());
  for (int p = 0; p < kernels::kLanes; ++p) {
    const int c = std::clamp(offset + p, 0, std::max(cols - 1, 0));
    px[p] = cols > 0 ? q_m(0, c) : 0.0;
    py[p] = cols > 0 ? q_m(1, c) : 0.0;
    pz[p] = cols > 0 ? q_m(2, c) : 0.0;
  }
}
}  // namespace

SwarmChannel::SwarmChannel(const ChannelModel& model, const Eigen::Matrix3Xd& q_m)
    : model_(&model),
      side_(q_m.cols() < model.num_antennas() ? GramSide::kUavs : GramSide::kBsAntennas),
      ld_(model.geometry().ld),
      H_(model.matrix(q_m)) {
  const int nr = num_uavs(), nt = model.num_antennas();
  row_re_.assign(static_cast<std::size_t>(ld_) * nr, 0.0);
  row_im_.assign(static_cast<std::size_t>(ld_) * nr, 0.0);
  for (int m = 0; m < nr; ++m) {
    for (int k = 0; k < nt; ++k) {
      row_re_[static_cast<std::size_t>(m) * ld_ + k] = H_(m, k).real();
      row_im_[static_cast<std::size_t>(m) * ld_ + k] = H_(m, k).imag();
    }
  }
  if (side_ == GramSide::kBsAntennas) {
    gram_re_.assign(static_cast<std::size_t>(ld_) * nt, 0.0);
    gram_im_.assign(static_cast<std::size_t>(ld_) * nt, 0.0);
  }
  refresh();
}

kernels::GramPlanes SwarmChannel::gram_planes() const {
  if (side_ == GramSide::kUavs)
    throw std::logic_error("SwarmChannel::gram_planes: the swarm keeps the UAVs' Gram matrix");
  return {model_->num_antennas(), ld_, gram_re_.data(), gram_im_.data()};
}

const Eigen::MatrixXcd& SwarmChannel::gram() const {
  if (side_ == GramSide::kUavs) return uav_gram_;
  if (gram_stale_) {
    const int nt = model_->num_antennas();
    gram_.resize(nt, nt);
    for (int k = 0; k < nt; ++k) {
      for (int l = 0; l < nt; ++l) {
        const std::size_t i = static_cast<std::size_t>(k) * ld_ + l;
        gram_(l, k) = std::complex<double>(gram_re_[i], gram_im_[i]);
      }
    }
    gram_stale_ = false;
  }
  return gram_;
}

bool SwarmChannel::gram_is_finite() const {
  if (finite_version_ == version_) return gram_finite_;
  gram_finite_ = side_ == GramSide::kUavs
                     ? detail::all_finite(uav_gram_)
                     : detail::all_finite(gram_re_.data(), static_cast<Eigen::Index>(gram_re_.size())) &&
                           detail::all_finite(gram_im_.data(), static_cast<Eigen::Index>(gram_im_.size()));
  finite_version_ = version_;
  return gram_finite_;
}

double SwarmChannel::objective() const {
  if (objective_version_ == version_) return objective_;
  if (side_ == GramSide::kUavs) {
    objective_ = uav_gram_objective();
  } else {
    // sum_{l != k} |G_lk|^2: the leave-one-out energy of a zero row.
    thread_local std::vector<double> zero;
    zero.assign(ld_, 0.0);
    objective_ = model_->kernels().leave_one_out_energy(gram_planes(), zero.data(), zero.data());
  }
  objective_version_ = version_;
  return objective_;
}

void SwarmChannel::set_position(int m, const Eigen::Vector3d& q_m) {
  thread_local std::vector<double> re, im;  // reused: no allocation per move
  re.resize(ld_);
  im.resize(ld_);
  model_->row_planes(q_m, re.data(), im.data());
  replace_row(m, re.data(), im.data());
}

void SwarmChannel::set_row(int m, const Eigen::VectorXcd& x) {
  thread_local std::vector<double> re, im;
  re.assign(ld_, 0.0);
  im.assign(ld_, 0.0);
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    re[k] = x(k).real();
    im[k] = x(k).imag();
  }
  replace_row(m, re.data(), im.data());
}

void SwarmChannel::set_positions(const Eigen::Matrix3Xd& q_m) {
  const int nr = num_uavs(), nt = model_->num_antennas();
  if (q_m.cols() != nr) {
    throw std::invalid_argument("SwarmChannel::set_positions: " + std::to_string(q_m.cols()) + " positions for " +
                                std::to_string(nr) + " UAVs");
  }
  // kLanes rows per rows_lanes call (the same bits as one row at a time, ~1.5x cheaper per row).
  constexpr int kLanes = kernels::kLanes;
  thread_local std::vector<double> Xr, Xi;
  Xr.resize(static_cast<std::size_t>(ld_) * kLanes);
  Xi.resize(static_cast<std::size_t>(ld_) * kLanes);
  for (int first = 0; first < nr; first += kLanes) {
    double px[kLanes], py[kLanes], pz[kLanes];
    positions_into_lanes(q_m, first, px, py, pz);  // unused lanes repeat the last UAV
    model_->kernels().rows_lanes(model_->geometry(), px, py, pz, Xr.data(), Xi.data());
    for (int p = 0; p < kLanes && first + p < nr; ++p) {
      const int m = first + p;
      double* re = row_re_.data() + static_cast<std::ptrdiff_t>(m) * ld_;
      double* im = row_im_.data() + static_cast<std::ptrdiff_t>(m) * ld_;
      for (int k = 0; k < ld_; ++k) {
        re[k] = Xr[static_cast<std::size_t>(k) * kLanes + p];
        im[k] = Xi[static_cast<std::size_t>(k) * kLanes + p];
      }
      for (int k = 0; k < nt; ++k) H_(m, k) = std::complex<double>(re[k], im[k]);
    }
  }
  if (side_ == GramSide::kUavs) {
    rebuild_uav_gram();
  } else {
    model_->kernels().gram_of_rows(row_re_.data(), row_im_.data(), nr, nt, ld_, gram_re_.data(), gram_im_.data());
  }
  gram_stale_ = true;
  updates_since_refresh_ = 0;
  ++version_;
}

void SwarmChannel::replace_row(int m, const double* re, const double* im) {
  // Remove the old row's outer product, add the new one: O(Nt^2).
  double* old_re = row_re_.data() + static_cast<std::ptrdiff_t>(m) * ld_;
  double* old_im = row_im_.data() + static_cast<std::ptrdiff_t>(m) * ld_;
  if (side_ == GramSide::kBsAntennas) {
    model_->kernels().gram_update(gram_re_.data(), gram_im_.data(), model_->num_antennas(), ld_, re, im, old_re,
                                  old_im);
  }
  for (int k = 0; k < ld_; ++k) {
    old_re[k] = re[k];
    old_im[k] = im[k];
  }
  if (side_ == GramSide::kUavs) update_uav_gram(m);
  for (Eigen::Index k = 0; k < H_.cols(); ++k) H_(m, k) = std::complex<double>(re[k], im[k]);
  gram_stale_ = true;
  ++version_;
  if (++updates_since_refresh_ >= kRefreshEvery) refresh();
}

void SwarmChannel::refresh() {
  if (side_ == GramSide::kUavs) {
    rebuild_uav_gram();
    updates_since_refresh_ = 0;
    ++version_;
    return;
  }
  const Eigen::MatrixXcd G = H_.adjoint() * H_;
  // Exactly Hermitian from here on (the updates keep it so): the product need not be.
  const int nt = model_->num_antennas();
  for (int k = 0; k < nt; ++k) {
    for (int l = 0; l < nt; ++l) {
      const std::complex<double> g = l == k  ? std::complex<double>(G(k, k).real(), 0.0)
                                     : l > k ? G(l, k)
                                             : std::conj(G(k, l));
      gram_re_[static_cast<std::size_t>(k) * ld_ + l] = g.real();
      gram_im_[static_cast<std::size_t>(k) * ld_ + l] = g.imag();
    }
  }
  gram_stale_ = true;
  updates_since_refresh_ = 0;
  ++version_;
}

UavObjective::UavObjective(const SwarmChannel& swarm, int m, Energy energy)
    : swarm_(&swarm), m_(m), version_(swarm.version()), energy_(energy) {
  if (m < 0 || m >= swarm.num_uavs()) {
    throw std::out_of_range("UavObjective: UAV " + std::to_string(m) + " of " + std::to_string(swarm.num_uavs()));
  }
}

void UavObjective::check_current() const {
  if (swarm_->version() != version_) {
    throw std::logic_error("UavObjective of UAV " + std::to_string(m_) + " used after the swarm's channel changed");
  }
}

double UavObjective::leave_one_out_energy() const {
  if (energy_ == Energy::kWithoutOthers) return 0.0;
  if (!have_F_A_) {
    F_A_ = uav_side() ? uav_side_others_energy()
                      : swarm_->model().kernels().leave_one_out_energy(swarm_->gram_planes(), swarm_->row_re(m_),
                                                                       swarm_->row_im(m_));
    have_F_A_ = true;
  }
  return F_A_;
}

double UavObjective::objective_of_row(const Eigen::VectorXcd& x) const {
  check_current();
  const int ld = swarm_->model().geometry().ld;
  thread_local std::vector<double> re, im;
  re.assign(ld, 0.0);
  im.assign(ld, 0.0);
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    re[k] = x(k).real();
    im[k] = x(k).imag();
  }
  if (uav_side()) return uav_side_objective(re.data(), im.data(), nullptr);
  return swarm_->model().kernels().objective_of_row(swarm_->gram_planes(), swarm_->row_re(m_), swarm_->row_im(m_),
                                                    leave_one_out_energy(), re.data(), im.data());
}

double UavObjective::objective_at(const Eigen::Vector3d& q_m) const {
  check_current();
  if (uav_side()) return uav_side_objective_at(q_m);
  const ChannelModel& model = swarm_->model();
  const double q[3] = {q_m.x(), q_m.y(), q_m.z()};
  return model.kernels().objective_at(model.geometry(), swarm_->gram_planes(), swarm_->row_re(m_), swarm_->row_im(m_),
                                      leave_one_out_energy(), q);
}

Eigen::Vector3d UavObjective::gradient_at(const Eigen::Vector3d& q_m, double* objective) const {
  check_current();
  if (uav_side()) {
    double grad[3];
    const double f = uav_side_gradient(q_m, grad);
    if (objective) *objective = f;
    return {grad[0], grad[1], grad[2]};
  }
  const ChannelModel& model = swarm_->model();
  const double q[3] = {q_m.x(), q_m.y(), q_m.z()};
  double grad[3];
  const double f = model.kernels().gradient(model.geometry(), swarm_->gram_planes(), swarm_->row_re(m_),
                                            swarm_->row_im(m_), leave_one_out_energy(), q, grad);
  if (objective) *objective = f;
  return {grad[0], grad[1], grad[2]};
}

void UavObjective::objectives_at(const Eigen::Ref<const Eigen::Matrix3Xd>& q_m, bool with_current_row,
                                 double* f) const {
  check_current();
  if (energy_ == Energy::kWithoutOthers) {
    throw std::logic_error(
        "UavObjective::objectives_at: the lanes kernel gives the whole f; build the view with "
        "Energy::kTotal");
  }
  constexpr int kLanes = kernels::kLanes;
  const int first = with_current_row ? 1 : 0;
  const int points = static_cast<int>(q_m.cols());
  if (uav_side()) {
    if (with_current_row) f[0] = uav_side_objective(swarm_->row_re(m_), swarm_->row_im(m_), nullptr);
    for (int c = 0; c < points; ++c) f[first + c] = uav_side_objective_at(q_m.col(c));
    return;
  }
  const ChannelModel& model = swarm_->model();
  const int ld = model.geometry().ld;
  thread_local std::vector<double> Xr, Xi;
  Xr.resize(static_cast<std::size_t>(ld) * kLanes);
  Xi.resize(static_cast<std::size_t>(ld) * kLanes);
  // Pass p fills the lanes with candidates p * kLanes ... (the current row first in pass 0);
  // every lane's value depends on that lane only, so passes agree with each other.
  const int count = first + points;
  for (int begin = 0; begin < count; begin += kLanes) {
    const bool stay = with_current_row && begin == 0;
    // Unused lanes repeat the last candidate (its f is computed and dropped).
    double px[kLanes], py[kLanes], pz[kLanes];
    positions_into_lanes(q_m, begin - first, px, py, pz);
    model.kernels().rows_lanes(model.geometry(), px, py, pz, Xr.data(), Xi.data());
    if (stay) {
      const double* re = swarm_->row_re(m_);
      const double* im = swarm_->row_im(m_);
      for (int k = 0; k < ld; ++k) {
        Xr[static_cast<std::size_t>(k) * kLanes] = re[k];
        Xi[static_cast<std::size_t>(k) * kLanes] = im[k];
      }
    }
    double all[kLanes];
    model.kernels().objectives_lanes(swarm_->gram_planes(), swarm_->row_re(m_), swarm_->row_im(m_), Xr.data(),
                                     Xi.data(), all);
    for (int p = 0; p < kLanes && begin + p < count; ++p) f[begin + p] = all[p];
  }
}

}  // namespace losmimo::placement
