// The shared association and bookkeeping around an associated-frame core
// (associating_backend.hpp).
#include "hapi_eskf/backend/associating_backend.hpp"

#include "hapi_eskf/backend/association.hpp"
#include "hapi_eskf/backend/association_source.hpp"
#include "hapi_eskf/backend/measurement_model.hpp"
#include "hapi_eskf/backend/stereo_frame_check.hpp"

#include <chrono>
#include <unordered_map>

namespace hapi_eskf {
namespace {

// The association's view of the pool: descriptors from the pool, marginals
// blockdiag(pose covariance, landmark covariance) per slot.
class PoolSource final : public AssociationSource {
 public:
  PoolSource(const DescriptorPool& pool, const Mat6& pose_cov, const std::vector<Mat3>& landmark_cov)
      : pool_(pool), pose_cov_(pose_cov), landmark_cov_(landmark_cov) {}
  int numLandmarks() const override { return static_cast<int>(landmark_cov_.size()); }
  Status matchDescriptors(const uint8_t* q, int n, std::vector<DescriptorMatch>* out) const override {
    return pool_.match(q, n, out);
  }
  Status marginals(const std::vector<int>& slots, std::vector<Mat9>* out) const override {
    if (!out) return Status::kInvalidArgument;
    out->assign(slots.size(), Mat9::Zero());
    for (std::size_t i = 0; i < slots.size(); ++i) {
      if (slots[i] < 0 || slots[i] >= numLandmarks()) return Status::kInvalidArgument;
      (*out)[i].topLeftCorner<6, 6>() = pose_cov_;
      (*out)[i].bottomRightCorner<3, 3>() = landmark_cov_[slots[i]];
    }
    return Status::kOk;
  }

 private:
  const DescriptorPool& pool_;
  const Mat6 pose_cov_;
  const std::vector<Mat3>& landmark_cov_;
};

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

AssociatingBackend::AssociatingBackend(const EskfSettings& settings, int descriptor_length,
                                       std::unique_ptr<AssociatedCore> core)
    : settings_(settings), core_(std::move(core)), pool_(descriptor_length) {}

std::size_t AssociatingBackend::memoryBytes() const { return core_->memoryBytes() + pool_.memoryBytes(); }

Status AssociatingBackend::reset(const PoseState& initial, double stamp) {
  const Status st = core_->reset(initial, stamp);
  if (st != Status::kOk) return st;
  pool_.clear();
  book_.clear();
  time_ = stamp;
  initialised_ = true;
  return Status::kOk;
}

Status AssociatingBackend::setCameraExtrinsic(const CameraExtrinsic& extrinsic) {
  // No IMU model: the extrinsic has nothing to move; it is only checked.
  return extrinsic.R_imu_cam.allFinite() && extrinsic.p_imu_cam.allFinite() ? Status::kOk : Status::kNonFinite;
}

Status AssociatingBackend::addImu(const ImuSample&) { return Status::kInvalidArgument; }

Status AssociatingBackend::predictTo(double stamp) {
  if (!initialised_) return Status::kNotInitialised;
  AssociatedFrame empty;
  empty.stamp = stamp;
  const Status st = core_->processAssociated(empty);
  if (st == Status::kOk) time_ = stamp;
  return st;
}

std::vector<LandmarkInfo> AssociatingBackend::landmarks() const {
  std::unordered_map<uint64_t, LandmarkInfo> all;
  for (const LandmarkInfo& l : core_->landmarks()) all.emplace(l.id, l);
  std::vector<LandmarkInfo> out;
  out.reserve(book_.size());
  for (const uint64_t id : book_.ids()) {
    const auto it = all.find(id);
    if (it != all.end()) out.push_back(it->second);
  }
  return out;
}

Status AssociatingBackend::processFrame(const StereoFrame& frame_in, IterationReport* report) {
  const auto t_start = std::chrono::steady_clock::now();
  IterationReport rep;
  rep.n_measurements = static_cast<int>(frame_in.measurements.size());
  auto finish = [&](Status s) {
    rep.n_landmarks = numLandmarks();
    rep.t_total_ms = msSince(t_start);
    if (report) *report = rep;
    return s;
  };
  if (!initialised_) return finish(Status::kNotInitialised);
  Status st = checkStereoFrame(frame_in, time_, pool_.length(), settings_.max_frame_measurements);
  if (st != Status::kOk) return finish(st);
  StereoFrame frame = frame_in;  // the filter's measurement model: re-detection term on C_z
  for (StereoMeasurement& m : frame.measurements)
    m.Cz += redetectionCovariance(m.z, settings_.measurement_angular_sigma);

  // --- association against the core's prediction ---
  auto t0 = std::chrono::steady_clock::now();
  PoseState predicted;
  Mat6 pose_cov;
  core_->predicted(frame.stamp, &predicted, &pose_cov);
  std::unordered_map<uint64_t, Mat3> cov_by_id;
  for (const LandmarkInfo& l : core_->landmarks()) cov_by_id.emplace(l.id, l.covariance);
  std::vector<Mat3> slot_cov(book_.size(), Mat3::Zero());
  for (int k = 0; k < book_.size(); ++k) {
    const auto it = cov_by_id.find(book_.ids()[k]);
    if (it != cov_by_id.end()) slot_cov[k] = it->second;
  }
  const PoolSource source(pool_, pose_cov, slot_cov);
  Association assoc;
  st = associate(frame, predicted, Mat6::Identity(), book_.positions(), source, settings_, &assoc);
  rep.t_association_ms = msSince(t0);
  if (st != Status::kOk) return finish(st);
  rep.n_candidates = assoc.n_candidates;
  rep.n_gated_out = assoc.n_gated_out;

  // --- the shared policy, on copies until the core accepts ---
  t0 = std::chrono::steady_clock::now();
  const std::vector<int> by_response = LandmarkBook::byResponse(frame);
  const std::vector<int> used = LandmarkBook::chooseUpdates(assoc, by_response, settings_);
  std::vector<char> used_slot(book_.size(), 0);
  AssociatedFrame af;
  af.stamp = frame.stamp;
  for (int i : used) {
    used_slot[assoc.slot[i]] = 1;
    const StereoMeasurement& m = frame.measurements[i];
    af.measurements.push_back(AssociatedMeasurement{book_.ids()[assoc.slot[i]], false, m.z, m.Cz, m.rgb});
  }
  const std::vector<int> add = book_.chooseAdditions(assoc, by_response, settings_);
  const std::vector<int> evict = book_.chooseRemovals(static_cast<int>(add.size()), used_slot, settings_);
  LandmarkBook book = book_;
  DescriptorPool pool = pool_;
  std::vector<uint64_t> evicted_ids;
  for (int k : evict) evicted_ids.push_back(book.ids()[k]);
  if (!evict.empty()) {
    pool.remove(evict);
    book.remove(evict);
  }
  const int n_add = book.additionsThatFit(static_cast<int>(add.size()), settings_);
  for (int j = 0; j < n_add; ++j) {
    const int i = add[j];
    const StereoMeasurement& m = frame.measurements[i];
    const uint64_t id = book.add(initLandmark(predicted, m.z), m.rgb, frame.stamp);
    pool.append(&frame.descriptors[static_cast<std::size_t>(i) * frame.descriptor_length]);
    af.measurements.push_back(AssociatedMeasurement{id, true, m.z, m.Cz, m.rgb});
  }
  st = core_->processAssociated(af);
  rep.t_update_ms = msSince(t0);
  if (st != Status::kOk) return finish(st);

  // --- accepted: commit the pool and the book, the core's estimates into it ---
  if (!evicted_ids.empty()) core_->forget(evicted_ids);
  book_ = std::move(book);
  pool_ = std::move(pool);
  time_ = frame.stamp;
  std::unordered_map<uint64_t, int> slot_of;
  for (int k = 0; k < book_.size(); ++k) slot_of.emplace(book_.ids()[k], k);
  for (const AssociatedMeasurement& m : af.measurements)
    if (!m.is_new) book_.observe(slot_of.at(m.landmark_id), frame.stamp, m.rgb);
  for (const LandmarkInfo& l : core_->landmarks()) {
    const auto it = slot_of.find(l.id);
    if (it != slot_of.end()) book_.position(it->second) = l.position;
  }
  rep.n_updated = static_cast<int>(used.size());
  rep.n_added = n_add;
  rep.n_removed = static_cast<int>(evict.size());
  return finish(Status::kOk);
}

std::unique_ptr<SlamBackend> makeAssociatingBackend(
    const EskfSettings& s, int descriptor_length,
    const std::function<std::unique_ptr<AssociatedCore>(std::string* error)>& makeCore, std::string* error) {
  if (s.motion_model != MotionModelKind::kConstantVelocity) {
    if (error) *error = std::string(toString(s.backend_algorithm)) + " supports motion_model constant_velocity only";
    return nullptr;
  }
  std::unique_ptr<AssociatedCore> core = makeCore(error);
  if (!core) return nullptr;
  auto backend = std::make_unique<AssociatingBackend>(s, descriptor_length, std::move(core));
  backend->reset(PoseState(), 0.0);
  return backend;
}

}  // namespace hapi_eskf
