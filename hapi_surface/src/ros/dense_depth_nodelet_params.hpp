// Private (~) parameters of hapi_surface/DenseDepthNodelet: the matcher's
// table (DenseDepthSettings) and the nodelet's own
// (dense_depth_nodelet_params.def), read and validated once at start-up.
#pragma once

#include "hapi_surface/dense_depth_settings.hpp"

#include <hapi_nodelet_kit/param_reader.hpp>

#include <string>

namespace hapi_surface {

struct DenseDepthNodeletParams {
  DenseDepthSettings depth;
#define HAPI_FIELD(type, name, default_value, range, unit, doc) type name = default_value;
#include "dense_depth_nodelet_params.def"
#undef HAPI_FIELD
};

// Every field of both tables (the matcher's first), visit(FieldInfo, field).
template <typename Visitor>
void forEachNodeletField(DenseDepthNodeletParams& p, Visitor&& visit) {
  forEachField(p.depth, visit);
#define HAPI_FIELD(type, name, default_value, range, unit, doc) visit(FieldInfo{#name, range, unit, doc}, p.name);
#include "dense_depth_nodelet_params.def"
#undef HAPI_FIELD
}

// Reads every ~ parameter through `reader` into *out (defaults for absent
// ones); a wrong type or a value out of its range is an error of `reader`,
// an unknown name a warning.
void readDenseDepthParams(hapi_nodelet_kit::ParamReader& reader, DenseDepthNodeletParams* out);

// Sets the field `name` of either table from text (dense_depth_link's
// key=value arguments); "" or why not.
std::string setDenseDepthParam(DenseDepthNodeletParams* p, const std::string& name, const std::string& value);

}  // namespace hapi_surface
