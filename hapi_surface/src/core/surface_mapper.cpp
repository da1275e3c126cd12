#include "hapi_surface/surface_mapper.hpp"

#include "hapi_surface/mesh_extraction.hpp"
#include "hapi_surface/sdf_registration.hpp"

#include <algorithm>

namespace hapi_surface {

SurfaceMapper::SurfaceMapper(const SurfaceSettings& s)
    : settings_(s),
      integrator_([](TsdfVolume* v, const DepthFrame& f) { return v->integrate(f); }),
      mesher_([](const TsdfVolume& v) { return extractMesh(v); }),
      gate_(s) {}

const Keyframe* SurfaceMapper::lastKeyframe() const {
  const Keyframe* fused = keyframes_.empty() ? nullptr : &keyframes_.back();
  const Keyframe* waiting = waiting_.empty() ? nullptr : &waiting_.back();
  if (!fused || !waiting) return fused ? fused : waiting;
  return fused->stamp >= waiting->stamp ? fused : waiting;
}

bool SurfaceMapper::isKeyframe(double stamp, const Eigen::Isometry3d& T) const {
  const Keyframe* k = lastKeyframe();
  if (!k) return true;
  const Keyframe& last = *k;
  return translationBetween(last.frame.T_world_camera, T) >= settings_.keyframe_translation ||
         rotationBetween(last.frame.T_world_camera, T) >= settings_.keyframe_rotation ||
         stamp - last.stamp >= settings_.keyframe_interval;
}

// The volume centred on the frame's median depth point (its surface), so the
// patch scanned from there lies inside.
SurfaceStatus SurfaceMapper::placeVolume(const DepthFrame& f) {
  std::vector<float> d;
  for (float z : f.depth.data)
    if (z >= settings_.min_depth && z <= settings_.max_depth) d.push_back(z);
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  const Eigen::Vector3d centre = f.T_world_camera * Eigen::Vector3d(0, 0, d[d.size() / 2]);
  const VoxelGrid grid = VoxelGrid::centredAt(centre, settings_);
  if (grid.size() > static_cast<std::size_t>(settings_.max_voxels)) return SurfaceStatus::kVolumeTooLarge;
  volume_ = std::make_unique<TsdfVolume>(grid, settings_);
  values_ = SurfaceValues(grid.size());
  return SurfaceStatus::kOk;
}

SurfaceStatus SurfaceMapper::addDepthFrame(double stamp, DepthFrame frame, const std::optional<Eigen::Isometry3d>& pose,
                                           FrameUse* use) {
  *use = FrameUse::kRejected;
  if (!pose) return SurfaceStatus::kNoPose;
  frame.T_world_camera = *pose;
  SurfaceStatus st = checkDepthFrame(frame, settings_);
  if (st != SurfaceStatus::kOk) return st;
  gate_.notePose(stamp);
  if (!isKeyframe(stamp, frame.T_world_camera)) {
    *use = FrameUse::kSkipped;
    return SurfaceStatus::kOk;
  }
  const std::size_t max_keyframes = static_cast<std::size_t>(settings_.max_keyframes);
  if (!gate_.settled(stamp)) {
    waiting_.push_back(Keyframe{stamp, std::move(frame)});
    for (; waiting_.size() > max_keyframes; ++waiting_discarded_) waiting_.pop_front();
    *use = FrameUse::kWaiting;
    return SurfaceStatus::kOk;
  }
  if (!volume_ && (st = placeVolume(frame)) != SurfaceStatus::kOk) return st;
  registerSettled(&frame);
  st = integrator_(volume_.get(), frame);
  if (st != SurfaceStatus::kOk) return st;
  keyframes_.push_back(Keyframe{stamp, std::move(frame)});
  if (!waiting_.empty() && keyframes_.size() >= static_cast<std::size_t>(settings_.settle_keyframes)) fuseWaiting();
  while (keyframes_.size() > max_keyframes) keyframes_.pop_front();
  mesh_stale_ = true;
  *use = FrameUse::kKeyframe;
  return SurfaceStatus::kOk;
}

void SurfaceMapper::registerSettled(DepthFrame* frame) {
  if (!settings_.register_keyframes || keyframes_.size() < static_cast<std::size_t>(settings_.settle_keyframes)) return;
  const Registration r = registerToSurface(*volume_, *frame);
  if (!r.accepted) {
    ++unregistered_;
    return;
  }
  frame->T_world_camera = r.T_world_camera;
  ++registered_;
}

void SurfaceMapper::fuseWaiting() {
  for (Keyframe& k : waiting_) {
    if (settings_.register_waiting) {
      const Registration r = registerToSurface(*volume_, k.frame);
      if (!r.accepted) {
        ++waiting_discarded_;
        continue;
      }
      k.frame.T_world_camera = r.T_world_camera;
    }
    if (integrator_(volume_.get(), k.frame) != SurfaceStatus::kOk) {
      ++waiting_discarded_;
      continue;
    }
    const auto at = std::upper_bound(keyframes_.begin(), keyframes_.end(), k.stamp,
                                     [](double t, const Keyframe& f) { return t < f.stamp; });
    keyframes_.insert(at, std::move(k));
    ++waiting_fused_;
  }
  waiting_.clear();
}

bool SurfaceMapper::correctPoses(const PoseCorrection& corrected) {
  bool rebuild = false;
  for (Keyframe& k : waiting_) {
    const std::optional<Eigen::Isometry3d> T = corrected(k.stamp, k.frame.T_world_camera);
    if (T && checkPose(*T) == SurfaceStatus::kOk) k.frame.T_world_camera = *T;
  }
  for (Keyframe& k : keyframes_) {
    const std::optional<Eigen::Isometry3d> T = corrected(k.stamp, k.frame.T_world_camera);
    if (!T || checkPose(*T) != SurfaceStatus::kOk) continue;
    if (translationBetween(k.frame.T_world_camera, *T) > settings_.rebuild_translation ||
        rotationBetween(k.frame.T_world_camera, *T) > settings_.rebuild_rotation)
      rebuild = true;
    k.frame.T_world_camera = *T;
  }
  if (!rebuild || !volume_) return false;
  volume_->clear();
  for (const Keyframe& k : keyframes_) integrator_(volume_.get(), k.frame);
  mesh_stale_ = true;
  ++rebuilds_;
  return true;
}

const Mesh& SurfaceMapper::mesh() {
  if (volume_ && mesh_stale_) {
    mesh_ = mesher_(*volume_);
    mesh_stale_ = false;
  }
  values_.sampleVertices(&mesh_);
  return mesh_;
}

ProjectionResult SurfaceMapper::addImagingFrame(const FloatImage& image, const PinholeCamera& camera,
                                                const std::optional<Eigen::Isometry3d>& T_world_camera) {
  ProjectionResult r;
  if (!T_world_camera) r.status = SurfaceStatus::kNoPose;
  else if (!volume_) r.status = SurfaceStatus::kNoVolume;
  if (r.status != SurfaceStatus::kOk) return r;
  const Mesh& m = mesh();
  return values_.addFrame(*volume_, m, image, camera, *T_world_camera);
}

}  // namespace hapi_surface
