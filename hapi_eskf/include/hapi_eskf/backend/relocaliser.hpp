// Relocalisation after an input outage (settings relocalise_gap, docs/DESIGN.md
// "Relocalisation"), the policy every back end shares: a frame more than
// relocalise_gap after the previous one is predicted from rest, and its pose
// mean is moved to the RANSAC rigid fit of the frame against the map
// (Association::fit_*, >= kRelocaliseMinInliers pairs) before gating; until
// such a fit, frames are held back (prediction only) for at most
// kRelocaliseWaitS, after which the back end carries on from the prediction.
// A loaded map (awaitMap) is the same wait without a time limit and with
// kMapRelocaliseMinInliers: the pose in the map is unknown until a fit.
// This class keeps the timeline (last frame, outage) and answers those
// questions; the back end moves its own pose.
#pragma once

#include "hapi_eskf/backend/association_settings.hpp"

namespace hapi_eskf {

class Relocaliser {
 public:
  explicit Relocaliser(const AssociationSettings& settings)
      : gap_(settings.relocalise_gap), can_fit_(settings.ransac_iterations > 0) {}

  // A new timeline starting at `stamp` (reset, gravity alignment).
  void reset(double stamp) {
    last_frame_stamp_ = stamp;
    pending_ = false;
    awaiting_map_ = false;
  }
  // A map was loaded: hold every frame until a fit places the camera in it.
  void awaitMap() {
    pending_ = can_fit_;
    awaiting_map_ = can_fit_;
  }
  bool awaitingMap() const { return awaiting_map_; }
  // The inliers a fit needs now.
  int minInliers() const { return awaiting_map_ ? kMapRelocaliseMinInliers : kRelocaliseMinInliers; }

  // Before the prediction of a frame at `stamp`: true when it follows an
  // outage (the back end predicts it from rest). Remembers the previous state
  // for rollback().
  bool beginFrame(double stamp) {
    saved_pending_ = pending_;
    saved_outage_ = outage_stamp_;
    const bool outage = gap_ > 0.0 && stamp - last_frame_stamp_ > gap_;
    if (outage) {
      pending_ = can_fit_;
      outage_stamp_ = stamp;
    }
    return outage;
  }
  // The frame was rejected before the back end changed anything.
  void rollback() {
    pending_ = saved_pending_;
    outage_stamp_ = saved_outage_;
  }
  // The frame's prediction succeeded: it is the last frame now. Returns the
  // stamp of the previous one.
  double acceptFrame(double stamp) {
    const double previous = last_frame_stamp_;
    last_frame_stamp_ = stamp;
    return previous;
  }

  // An outage was seen and no map fit has moved the pose yet.
  bool pending() const { return pending_; }
  // The pose mean was moved to the frame's map fit; true when that ended a
  // relocalisation (IterationReport::relocalised).
  bool fitApplied() {
    const bool was = pending_;
    pending_ = false;
    awaiting_map_ = false;
    return was;
  }
  // Still pending after the association of the frame at `stamp`: true =
  // hold the frame back (prediction only, IterationReport::relocalising);
  // false = the wait is over, carry on from the prediction.
  bool holdFrame(double stamp) {
    if (!pending_) return false;
    if (awaiting_map_ || stamp - outage_stamp_ <= kRelocaliseWaitS) return true;
    pending_ = false;
    return false;
  }

 private:
  double gap_;
  bool can_fit_;
  double last_frame_stamp_ = 0.0, outage_stamp_ = 0.0;
  bool pending_ = false;
  bool awaiting_map_ = false;
  bool saved_pending_ = false;
  double saved_outage_ = 0.0;
};

}  // namespace hapi_eskf
