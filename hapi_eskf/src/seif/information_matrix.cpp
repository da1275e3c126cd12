// Block-sparse information matrix of the SEIF (information_matrix.hpp).
#include "hapi_eskf/seif/information_matrix.hpp"

#include <algorithm>

namespace hapi_eskf {
namespace seif {

void InformationMatrix::reset(const PoseMat& omega_xx) {
  xx_ = omega_xx;
  xi_x_ = PoseVec::Zero(omega_xx.rows());
  xm_.clear();
  is_active_.clear();
  active_.clear();
  mm_.clear();
  xi_m_.clear();
  links_.clear();
}

Eigen::MatrixXd InformationMatrix::gather(const std::vector<int>& slots) const {
  const int P = poseDim(), n = P + 3 * static_cast<int>(slots.size());
  // Row of each gathered slot (-1: not gathered). A plain array: every link
  // of every gathered slot is looked up, and a landmark has hundreds of links
  // once the pool is full (a hash map made this the SEIF's hottest loop).
  std::vector<int> local(numLandmarks(), -1);
  for (std::size_t i = 0; i < slots.size(); ++i) local[slots[i]] = P + 3 * static_cast<int>(i);
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n);
  M.topLeftCorner(P, P) = xx_;
  for (std::size_t i = 0; i < slots.size(); ++i) {
    const int k = slots[i], r = P + 3 * static_cast<int>(i);
    if (is_active_[k]) {
      M.block(0, r, P, 3) = xm_[k];
      M.block(r, 0, 3, P) = xm_[k].transpose();
    }
    M.block<3, 3>(r, r) = mm_[k];
    forEachLinkAmong(k, slots, [&](int j, const Mat3& B) {
      if (local[j] >= 0) M.block<3, 3>(r, local[j]) = B;
    });
  }
  return M;
}

Eigen::VectorXd InformationMatrix::gatherXi(const std::vector<int>& slots) const {
  const int P = poseDim();
  Eigen::VectorXd v(P + 3 * slots.size());
  v.head(P) = xi_x_;
  for (std::size_t i = 0; i < slots.size(); ++i) v.segment<3>(P + 3 * i) = xi_m_[slots[i]];
  return v;
}

void InformationMatrix::scatter(const std::vector<int>& slots, const Eigen::MatrixXd& M) {
  const int P = poseDim();
  xx_ = 0.5 * (M.topLeftCorner(P, P) + M.topLeftCorner(P, P).transpose());
  for (std::size_t i = 0; i < slots.size(); ++i) {
    const int k = slots[i], r = P + 3 * static_cast<int>(i);
    const PoseLink L = 0.5 * (M.block(0, r, P, 3) + M.block(r, 0, 3, P).transpose());
    const bool linked = !L.isZero(0.0);
    setActive(k, linked);
    xm_[k] = linked ? L : PoseLink::Zero(P, 3);
    mm_[k] = 0.5 * (M.block<3, 3>(r, r) + M.block<3, 3>(r, r).transpose());
    for (std::size_t t = i + 1; t < slots.size(); ++t) {
      const int j = slots[t], c = P + 3 * static_cast<int>(t);
      const Mat3 B = 0.5 * (M.block<3, 3>(r, c) + M.block<3, 3>(c, r).transpose());
      if (B.isZero(0.0)) {
        links_[k].erase(j);
        links_[j].erase(k);
      } else {
        links_[k][j] = B;
        links_[j][k] = B.transpose();
      }
    }
  }
}

void InformationMatrix::scatterXi(const std::vector<int>& slots, const Eigen::VectorXd& v) {
  const int P = poseDim();
  xi_x_ = v.head(P);
  for (std::size_t i = 0; i < slots.size(); ++i) xi_m_[slots[i]] = v.segment<3>(P + 3 * i);
}

int InformationMatrix::appendLandmark() {
  const int P = poseDim();
  xm_.push_back(PoseLink::Zero(P, 3));
  is_active_.push_back(0);
  mm_.push_back(Mat3::Zero());
  xi_m_.push_back(Vec3::Zero());
  links_.emplace_back();
  return numLandmarks() - 1;
}

void InformationMatrix::setActive(int slot, bool on) {
  if ((is_active_[slot] != 0) == on) return;
  is_active_[slot] = on ? 1 : 0;
  if (on)
    active_.push_back(slot);
  else
    active_.erase(std::find(active_.begin(), active_.end(), slot));
}

void InformationMatrix::dropLandmark(int slot) {
  for (const auto& [j, B] : links_[slot]) links_[j].erase(slot);
  links_[slot].clear();
  setActive(slot, false);
  xm_[slot].setZero();
  mm_[slot].setZero();
  xi_m_[slot].setZero();
}

void InformationMatrix::moveLandmark(int from, int to) {
  for (const auto& [j, B] : links_[from]) {
    links_[j].erase(from);
    links_[j][to] = B.transpose();
  }
  links_[to] = std::move(links_[from]);
  links_[from].clear();
  const bool was_active = is_active_[from] != 0;
  setActive(from, false);
  xm_[to] = xm_[from];
  setActive(to, was_active);
  mm_[to] = mm_[from];
  xi_m_[to] = xi_m_[from];
}

void InformationMatrix::truncate(int K) {
  xm_.resize(K);
  is_active_.resize(K);
  mm_.resize(K);
  xi_m_.resize(K);
  links_.resize(K);
}

std::size_t InformationMatrix::memoryBytes() const {
  std::size_t links = 0;
  for (const auto& l : links_) links += l.size();
  return sizeof(double) * (xx_.size() + mm_.size() * (9 + 3 + 3 * poseDim()) + links * 9) + links * 16;
}

}  // namespace seif
}  // namespace hapi_eskf
