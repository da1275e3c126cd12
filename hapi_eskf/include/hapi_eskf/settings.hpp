// The settings of hapi_eskf: one options struct composed of one table per
// part (as open_vins's VioManagerOptions composes its parts), each declared
// once in its .def list (field_table.hpp says why):
//  * PoolSettings (backend/pool_settings.hpp), AssociationSettings
//    (backend/association_settings.hpp), MeasurementSettings
//    (backend/measurement_settings.hpp): what every back end shares;
//  * StorageSettings (covariance/storage_settings.hpp), MotionSettings
//    (backend/motion_settings.hpp): the ES-EKF's (and the SEIF's host logic's);
//  * seif, graph, fastslam: each further algorithm's own table.
// The shared and the ES-EKF's parts are bases, so the filter reads
// settings.max_landmarks; the other algorithms' parts are members, and each
// algorithm is handed only its own part. The ROS parameter names stay flat:
// the members' fields are seif_<name>, graph_<name> and fastslam_<name>
// there (config/eskf.yaml), in tools' key=value and in forEachField.
#pragma once

#include "hapi_eskf/backend/association_settings.hpp"
#include "hapi_eskf/backend/measurement_settings.hpp"
#include "hapi_eskf/backend/motion_settings.hpp"
#include "hapi_eskf/backend/pool_settings.hpp"
#include "hapi_eskf/covariance/storage_settings.hpp"
#include "hapi_eskf/fastslam/fastslam_settings.hpp"
#include "hapi_eskf/field_table.hpp"
#include "hapi_eskf/graph/graph_settings.hpp"
#include "hapi_eskf/seif/seif_settings.hpp"

#include <string>
#include <type_traits>

namespace hapi_eskf {

// The SLAM algorithm behind the back-end interface (slam_backend.hpp).
enum class BackendAlgorithm { kEskf, kSeif, kGraph, kFastSlam2 };

template <>
struct EnumNames<BackendAlgorithm> {
  static constexpr EnumName<BackendAlgorithm> kNames[] = {{BackendAlgorithm::kEskf, "eskf"},
                                                          {BackendAlgorithm::kSeif, "seif"},
                                                          {BackendAlgorithm::kGraph, "graph"},
                                                          {BackendAlgorithm::kFastSlam2, "fastslam2"}};
};

struct EskfSettings : PoolSettings, StorageSettings, AssociationSettings, MeasurementSettings, MotionSettings {
  // Every algorithm shares the association, bookkeeping and relocalisation
  // settings; the storage settings are the ES-EKF's only.
  BackendAlgorithm backend_algorithm = BackendAlgorithm::kEskf;
  seif::SeifSettings seif;
  graph::GraphTable graph;
  fastslam::FastSlamTable fastslam;

  // Empty when valid, else a message naming the offending field and its
  // range: every field against its table range, then the rules between
  // fields (PoolSettings::crossFieldError).
  std::string validate() const;
};

// Calls visit(const FieldInfo&, field) for every field of `s`, the parts in
// the order of config/eskf.yaml; the field is `const T&` or `T&` as `s` is
// const or not. The members' fields carry their prefix in FieldInfo::name.
HAPI_SETTINGS_VISITOR(EskfSettings) {
  forEachField(asPart<PoolSettings>(s), visit);
  visit(FieldInfo{"backend_algorithm", Range::any(), "",
                  "SLAM back end: eskf (error-state EKF), seif (sparse extended information filter), graph, "
                  "fastslam2"},
        s.backend_algorithm);
#define HAPI_FIELD(type, name, default_value, range, unit, doc) \
  visit(FieldInfo{"seif_" #name, range, unit, doc}, s.seif.name);
#include "hapi_eskf/seif/seif_settings.def"
#undef HAPI_FIELD
#define HAPI_GRAPH_FIELD(type, name, default_value, range, unit, doc) \
  visit(FieldInfo{"graph_" #name, range, unit, "graph: " doc}, s.graph.name);
#include "hapi_eskf/graph/graph_settings.def"
#undef HAPI_GRAPH_FIELD
#define HAPI_FASTSLAM_FIELD(type, name, default_value, range, unit, doc) \
  visit(FieldInfo{"fastslam_" #name, range, unit, "fastslam2: " doc}, s.fastslam.name);
#include "hapi_eskf/fastslam/fastslam_settings.def"
#undef HAPI_FASTSLAM_FIELD
  forEachField(asPart<StorageSettings>(s), visit);
  forEachField(asPart<AssociationSettings>(s), visit);
  forEachField(asPart<MeasurementSettings>(s), visit);
  forEachField(asPart<MotionSettings>(s), visit);
}

// Sets the field called `name` from its text form (tool command lines,
// "ransac_iterations=0"). Empty on success, else why not (unknown name,
// unparsable value); the range is checked by validate(), not here.
std::string setFieldFromText(EskfSettings* s, const std::string& name, const std::string& value);

const char* toString(BackendAlgorithm a);

}  // namespace hapi_eskf
