// Block-sparse storage of the SEIF's error-state information matrix Omega and
// information vector xi (docs/DESIGN.md "SEIF"): the pose block, a P x 3 link
// from the pose to each ACTIVE landmark, each landmark's 3x3 diagonal block
// and the 3x3 links between landmarks (kept in both directions). The SEIF's
// operations work on small dense gathers of it (pose + a list of slots) and
// scatter the result back, so their cost depends on the list, not on K.
#pragma once

#include "hapi_eskf/types.hpp"

#include <Eigen/Core>

#include <unordered_map>
#include <vector>

namespace hapi_eskf {
namespace seif {

using PoseLink = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::ColMajor, kMaxPoseDim, 3>;

class InformationMatrix {
 public:
  // Omega := Omega_xx (P x P), no landmarks, xi := 0.
  void reset(const PoseMat& omega_xx);
  int poseDim() const { return static_cast<int>(xx_.rows()); }
  int numLandmarks() const { return static_cast<int>(mm_.size()); }
  // Landmarks linked to the pose, in the order they became active.
  const std::vector<int>& active() const { return active_; }
  bool isActive(int slot) const { return is_active_[slot] != 0; }
  const std::unordered_map<int, Mat3>& links(int slot) const { return links_[slot]; }
  // f(j, Omega_slot,j) for the links of `slot` to the slots in `among` (in
  // no particular order; `among` may hold `slot` itself, which has no
  // link): by walking the slot's links, or by looking each of `among` up
  // when that is the shorter list. A landmark seen with many others has
  // hundreds of links, and each step of a walk is a cache miss.
  template <typename F>
  void forEachLinkAmong(int slot, const std::vector<int>& among, F&& f) const {
    const auto& L = links_[slot];
    if (L.size() <= among.size()) {
      for (const auto& [j, B] : L) f(j, B);
      return;
    }
    for (int j : among) {
      const auto it = L.find(j);
      if (it != L.end()) f(j, it->second);
    }
  }
  const Mat3& diagonal(int slot) const { return mm_[slot]; }
  const PoseMat& poseBlock() const { return xx_; }
  const Vec3& xiLandmark(int slot) const { return xi_m_[slot]; }

  // Dense Omega and xi over [pose, slots...] (P + 3 |slots| rows, in that order).
  Eigen::MatrixXd gather(const std::vector<int>& slots) const;
  Eigen::VectorXd gatherXi(const std::vector<int>& slots) const;
  // Writes those blocks back: links that are exactly zero are dropped, a
  // landmark whose pose link is exactly zero becomes passive.
  void scatter(const std::vector<int>& slots, const Eigen::MatrixXd& omega);
  void scatterXi(const std::vector<int>& slots, const Eigen::VectorXd& xi);
  void addXiLandmark(int slot, const Vec3& d) { xi_m_[slot] += d; }
  void addDiagonal(int slot, const Mat3& d) { mm_[slot] += d; }
  void setXiLandmark(int slot, const Vec3& v) { xi_m_[slot] = v; }

  // A new landmark slot K (no links, zero information) to be filled by scatter.
  int appendLandmark();
  // Drops the slot's every entry (it must already be marginalised out: the
  // neighbours' links to it are erased here).
  void dropLandmark(int slot);
  // Renames slot `from` to `to` (a dropped slot), links included.
  void moveLandmark(int from, int to);
  void truncate(int K);  // after the moves: slots >= K are gone

  std::size_t memoryBytes() const;

 private:
  void setActive(int slot, bool on);

  PoseMat xx_;
  PoseVec xi_x_;
  std::vector<PoseLink> xm_;
  std::vector<char> is_active_;
  std::vector<int> active_;
  std::vector<Mat3> mm_;
  std::vector<Vec3> xi_m_;
  std::vector<std::unordered_map<int, Mat3>> links_;
};

}  // namespace seif
}  // namespace hapi_eskf
