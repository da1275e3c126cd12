// The surface of a scan: keyframes, the TSDF volume built from them, its
// mesh and the imaging values on it (docs/DESIGN.md "Surface",
// re-integration policy).
//
// Only keyframes are fused (a depth frame after enough camera motion or
// time), and every keyframe is kept (up to max_keyframes, the oldest
// dropped), so the volume is exactly the fusion of the stored keyframes.
// When the filter corrects past poses, correctPoses() takes the new pose of
// each stored keyframe; if one moved by more than rebuild_translation /
// rebuild_rotation, the volume is cleared and rebuilt from the keyframes at
// their new poses (de-integrating one keyframe is not exact once a voxel's
// weight reached max_weight, a rebuild always is).
//
// A keyframe whose filter pose is not settled (SettleGate) waits instead of
// being fused; once settle_keyframes settled keyframes are fused, the
// waiting ones are registered to their surface (register_waiting) and fused
// at the registered pose, or discarded when they do not register. So the
// filter's start-up error leaves no displaced sheet in the volume and the
// early views still count.
#pragma once

#include "hapi_surface/mesh.hpp"
#include "hapi_surface/settle_gate.hpp"
#include "hapi_surface/surface_values.hpp"
#include "hapi_surface/tsdf_volume.hpp"

#include <deque>
#include <functional>
#include <memory>
#include <optional>

namespace hapi_surface {

struct Keyframe {
  double stamp = 0;
  DepthFrame frame;
};

// What addDepthFrame did with a frame: a keyframe fused, or waiting for a
// settled filter.
enum class FrameUse { kRejected, kSkipped, kKeyframe, kWaiting };

// What became of the keyframes that waited for a settled filter.
struct WaitingCounts {
  std::size_t waiting = 0;     // now
  std::size_t fused = 0;       // registered (or taken at the filter's pose) and fused
  std::size_t discarded = 0;   // did not register, or dropped beyond max_keyframes
  std::size_t registered = 0;  // settled keyframes registered (register_keyframes)
  std::size_t unregistered = 0;  // settled keyframes fused at the filter's pose: did not register
};

// Fuses a depth frame into the volume (CPU or a GPU integrator).
using Integrator = std::function<SurfaceStatus(TsdfVolume*, const DepthFrame&)>;
// The mesh of a volume (extractMesh, with or without the GPU's active cells).
using Mesher = std::function<Mesh(const TsdfVolume&)>;

class SurfaceMapper {
 public:
  explicit SurfaceMapper(const SurfaceSettings& s);

  // The integrator (default: TsdfVolume::integrate).
  void setIntegrator(Integrator integrator) { integrator_ = std::move(integrator); }
  // The mesher (default: extractMesh on the CPU alone).
  void setMesher(Mesher mesher) { mesher_ = std::move(mesher); }

  // The filter's pose uncertainty at a stamp (odometry), for the settle rule.
  void addPoseUncertainty(const PoseUncertainty& u) { gate_.addUncertainty(u); }

  // A depth frame at `stamp` (its T_world_camera is replaced by `pose`;
  // nullopt: no pose known for the stamp -> kNoPose). The first fused frame
  // places the volume (centred on its median depth point). *use says whether
  // it became a keyframe, fused or waiting. On any error nothing changes.
  SurfaceStatus addDepthFrame(double stamp, DepthFrame frame, const std::optional<Eigen::Isometry3d>& pose,
                              FrameUse* use);

  // New poses of the stored keyframes: corrected(stamp, current pose)
  // (nullopt: unchanged). Returns true when the volume was rebuilt.
  using PoseCorrection = std::function<std::optional<Eigen::Isometry3d>(double, const Eigen::Isometry3d&)>;
  bool correctPoses(const PoseCorrection& corrected);

  // The current mesh (re-extracted when the volume changed), with values.
  const Mesh& mesh();

  // Projects an imaging frame onto the current surface (kNoVolume before
  // the first keyframe, kNoPose without a pose).
  ProjectionResult addImagingFrame(const FloatImage& image, const PinholeCamera& camera,
                                   const std::optional<Eigen::Isometry3d>& T_world_camera);

  const TsdfVolume* volume() const { return volume_.get(); }
  const std::deque<Keyframe>& keyframes() const { return keyframes_; }
  WaitingCounts waitingCounts() const {
    return {waiting_.size(), waiting_fused_, waiting_discarded_, registered_, unregistered_};
  }
  std::size_t rebuilds() const { return rebuilds_; }

 private:
  bool isKeyframe(double stamp, const Eigen::Isometry3d& T) const;
  SurfaceStatus placeVolume(const DepthFrame& frame);
  // The newest keyframe, fused or waiting (nullptr: none).
  const Keyframe* lastKeyframe() const;
  // Registers and fuses the waiting keyframes (in stamp order among the
  // fused ones).
  void fuseWaiting();
  // A settled keyframe's pose registered to the surface (register_keyframes).
  void registerSettled(DepthFrame* frame);

  SurfaceSettings settings_;
  Integrator integrator_;
  Mesher mesher_;
  std::unique_ptr<TsdfVolume> volume_;
  SurfaceValues values_;
  std::deque<Keyframe> keyframes_;
  SettleGate gate_;
  std::deque<Keyframe> waiting_;
  std::size_t waiting_fused_ = 0, waiting_discarded_ = 0, registered_ = 0, unregistered_ = 0;
  Mesh mesh_;
  bool mesh_stale_ = true;
  std::size_t rebuilds_ = 0;
};

}  // namespace hapi_surface
