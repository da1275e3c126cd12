// The FastSLAM 2.0 filter loop, resampling and outputs (fastslam2.hpp;
// docs/DESIGN.md "FastSLAM 2.0").
#include "hapi_eskf/backend/pose_kinematics.hpp"
#include "hapi_eskf/fastslam/fastslam2.hpp"

#include "hapi_eskf/so3.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_set>

namespace hapi_eskf {
namespace fastslam {

FastSlam2::FastSlam2(const FastSlamSettings& settings) : settings_(settings) {}

Status FastSlam2::reset(const PoseState& initial, double stamp) {
  if (!settings_.validate().empty()) return Status::kInvalidArgument;
  if (!std::isfinite(stamp) || !initial.p.allFinite() || !initial.q.coeffs().allFinite()) return Status::kNonFinite;
  if (initial.q.norm() < 1e-6) return Status::kInvalidArgument;
  Particle p0;
  p0.p = initial.p;
  p0.q = initial.q.normalized();
  p0.v = p0.q * initial.v;  // PoseState's v is in the camera frame, the particle's in the world
  p0.w = initial.w;
  particles_.assign(settings_.num_particles, p0);
  slot_.clear();
  ids_.clear();
  rgb_.clear();
  times_observed_.clear();
  last_seen_.clear();
  time_ = stamp;
  frame_count_ = 0;
  initialised_ = true;
  return Status::kOk;
}

Mat6 FastSlam2::processNoise(double dt) const {
  return poseRandomWalkNoise(dt, settings_.sigma_acceleration, settings_.sigma_angular_acceleration);
}

Status FastSlam2::processFrame(const AssociatedFrame& frame, FastSlamReport* report) {
  FastSlamReport rep;
  if (!initialised_) return Status::kNotInitialised;
  const Status st = checkAssociatedFrame(frame, time_, [this](uint64_t id) { return slot_.count(id) > 0; });
  if (st != Status::kOk) return st;

  std::vector<SlotMeasurement> meas;
  meas.reserve(frame.measurements.size());
  int next_slot = numLandmarks();
  for (const AssociatedMeasurement& m : frame.measurements) {
    SlotMeasurement s;
    s.is_new = m.is_new;
    s.slot = m.is_new ? next_slot++ : slot_.at(m.landmark_id);
    s.z = m.z;
    s.Cz = m.Cz;
    meas.push_back(s);
    (m.is_new ? rep.n_added : rep.n_known) += 1;
  }
  // New landmarks in slot order (stepParticle appends them in measurement order).
  const double dt = frame.stamp - time_;
  const Mat6 Q = processNoise(dt);
  std::vector<Particle> next = particles_;
  const int n = static_cast<int>(next.size());
  std::vector<char> ok(n, 1);
#pragma omp parallel for schedule(dynamic, 8)
  for (int i = 0; i < n; ++i) {
    // Per particle and frame, independent of the thread that runs it.
    std::seed_seq seq{static_cast<uint32_t>(settings_.seed), static_cast<uint32_t>(frame_count_),
                      static_cast<uint32_t>(frame_count_ >> 32), static_cast<uint32_t>(i)};
    std::mt19937 rng(seq);
    ok[i] = stepParticle(meas, dt, Q, rng, &next[i]) ? 1 : 0;
  }
  // A particle whose step failed cannot carry the new landmarks: the frame is
  // rejected as a whole (state unchanged) when that happens.
  if (std::find(ok.begin(), ok.end(), 0) != ok.end()) return Status::kNotPositiveDefinite;

  particles_ = std::move(next);
  for (const AssociatedMeasurement& m : frame.measurements) {
    if (m.is_new) {
      slot_.emplace(m.landmark_id, static_cast<int>(ids_.size()));
      ids_.push_back(m.landmark_id);
      rgb_.push_back(m.rgb);
      times_observed_.push_back(0);
      last_seen_.push_back(frame.stamp);
    }
    const int k = slot_.at(m.landmark_id);
    rgb_[k] = m.rgb;
    ++times_observed_[k];
    last_seen_[k] = frame.stamp;
  }
  time_ = frame.stamp;
  ++frame_count_;

  // Normalise the log weights (log-sum-exp), then N_eff = 1 / sum w^2.
  double top = -std::numeric_limits<double>::infinity();
  for (const Particle& p : particles_) top = std::max(top, p.log_weight);
  double sum = 0.0;
  for (const Particle& p : particles_) sum += std::exp(p.log_weight - top);
  const double log_sum = top + std::log(sum);
  double sum_sq = 0.0;
  for (Particle& p : particles_) {
    p.log_weight -= log_sum;
    sum_sq += std::exp(2.0 * p.log_weight);
  }
  rep.effective_sample_size = 1.0 / sum_sq;
  if (rep.effective_sample_size < settings_.resample_threshold * n) {
    resample();
    rep.resampled = true;
  }
  if (report) *report = rep;
  return Status::kOk;
}

// Systematic (low-variance) resampling: one uniform offset, n equally spaced
// pointers into the cumulative weights; weights become uniform.
void FastSlam2::resample() {
  const int n = static_cast<int>(particles_.size());
  std::mt19937 rng(static_cast<uint32_t>(settings_.seed) ^ static_cast<uint32_t>(0x9e3779b9u * frame_count_));
  const double u0 = std::uniform_real_distribution<double>(0.0, 1.0 / n)(rng);
  std::vector<Particle> out;
  out.reserve(n);
  double cum = std::exp(particles_[0].log_weight);
  int j = 0;
  for (int i = 0; i < n; ++i) {
    const double u = u0 + static_cast<double>(i) / n;
    while (u > cum && j < n - 1) cum += std::exp(particles_[++j].log_weight);
    out.push_back(particles_[j]);
    out.back().log_weight = -std::log(static_cast<double>(n));
  }
  particles_ = std::move(out);
}

void FastSlam2::predicted(double stamp, PoseState* pose_out, Mat6* covariance) const {
  PoseState x = pose();
  const double dt = std::max(0.0, stamp - time_);
  x.p += x.q * x.v * dt;  // v, w of pose() are in the camera frame
  x.q = (x.q * quatExp(x.w * dt)).normalized();
  *pose_out = x;
  *covariance = poseCovariance() + processNoise(dt);
}

void FastSlam2::forget(const std::vector<uint64_t>& ids) {
  for (const uint64_t id : ids) {
    const auto it = slot_.find(id);
    if (it == slot_.end()) continue;
    const int k = it->second, last = static_cast<int>(ids_.size()) - 1;
    // Tail fill: the last slot moves into k in every particle and every table.
    for (Particle& p : particles_) {
      p.map[k] = p.map[last];
      p.map.pop_back();
    }
    slot_.erase(it);
    if (k != last) {
      ids_[k] = ids_[last];
      rgb_[k] = rgb_[last];
      times_observed_[k] = times_observed_[last];
      last_seen_[k] = last_seen_[last];
      slot_[ids_[k]] = k;
    }
    ids_.pop_back();
    rgb_.pop_back();
    times_observed_.pop_back();
    last_seen_.pop_back();
  }
}

std::size_t FastSlam2::memoryBytes() const {
  // Every particle's pointer table, and each shared EKF once.
  std::size_t bytes = particles_.size() * sizeof(Particle);
  std::unordered_set<const LandmarkEkf*> ekfs;
  for (const Particle& p : particles_) {
    bytes += p.map.capacity() * sizeof(p.map[0]);
    for (const auto& l : p.map) ekfs.insert(l.get());
  }
  return bytes + ekfs.size() * sizeof(LandmarkEkf);
}

std::vector<double> FastSlam2::weights() const {
  std::vector<double> w;
  w.reserve(particles_.size());
  for (const Particle& p : particles_) w.push_back(std::exp(p.log_weight));
  double s = 0.0;
  for (double x : w) s += x;
  for (double& x : w) x /= s;
  return w;
}

PoseState FastSlam2::pose() const {
  PoseState out;
  if (particles_.empty()) return out;
  const std::vector<double> w = weights();
  std::size_t best = 0;
  for (std::size_t i = 0; i < w.size(); ++i) {
    out.p += w[i] * particles_[i].p;
    out.v += w[i] * particles_[i].v;
    out.w += w[i] * particles_[i].w;
    if (w[i] > w[best]) best = i;
  }
  // Karcher mean on SO(3) from the best particle: R <- R Exp(sum w Log(R^T R_i)).
  Mat3 R = particles_[best].q.toRotationMatrix();
  for (int it = 0; it < 5; ++it) {
    Vec3 d = Vec3::Zero();
    for (std::size_t i = 0; i < w.size(); ++i) d += w[i] * logSO3(R.transpose() * particles_[i].q.toRotationMatrix());
    R = R * expSO3(d);
    if (d.norm() < 1e-12) break;
  }
  out.q = Eigen::Quaterniond(R).normalized();
  out.v = out.q.conjugate() * out.v;  // types.hpp: v in the camera frame
  return out;
}

Mat6 FastSlam2::poseCovariance() const {
  Mat6 C = Mat6::Zero();
  if (particles_.empty()) return C;
  const std::vector<double> w = weights();
  const PoseState m = pose();
  const Mat3 Rt = m.q.toRotationMatrix().transpose();
  for (std::size_t i = 0; i < w.size(); ++i) {
    Eigen::Matrix<double, 6, 1> e;
    e.head<3>() = particles_[i].p - m.p;
    e.tail<3>() = logSO3(Rt * particles_[i].q.toRotationMatrix());
    C += w[i] * e * e.transpose();
  }
  return C;
}

std::vector<LandmarkInfo> FastSlam2::landmarks() const {
  std::vector<LandmarkInfo> out(ids_.size());
  const std::vector<double> w = weights();
  for (std::size_t k = 0; k < ids_.size(); ++k) {
    LandmarkInfo& l = out[k];
    l.id = ids_[k];
    l.rgb = rgb_[k];
    l.times_observed = times_observed_[k];
    l.last_seen = last_seen_[k];
    // Mixture of the particles' Gaussians: mean sum w mu, covariance
    // sum w (Sigma + (mu - mean)(mu - mean)^T).
    for (std::size_t i = 0; i < w.size(); ++i) l.position += w[i] * particles_[i].map[k]->mean;
    for (std::size_t i = 0; i < w.size(); ++i) {
      const LandmarkEkf& e = *particles_[i].map[k];
      const Vec3 d = e.mean - l.position;
      l.covariance += w[i] * (e.cov + d * d.transpose());
    }
  }
  return out;
}

}  // namespace fastslam
}  // namespace hapi_eskf
