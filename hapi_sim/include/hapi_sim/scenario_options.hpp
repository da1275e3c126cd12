// The scenario's command-line options, one parser for every tool that
// simulates a recording (make_sim_bag writes it, pipeline_latency runs the
// whole pipeline on it): the names, the value checks and the usage text.
// ROS-free.
#pragma once

#include <string>

#include "hapi_sim/scenario.hpp"

namespace hapi_sim {

// The options' usage lines, to print in a tool's usage.
extern const char* const kScenarioOptionsUsage;

// Sets the field of *cfg that the option `key` (e.g. "--seed") names from
// `value`. Returns false when `key` is no scenario option (the tool's own,
// then). Throws std::invalid_argument with the message to print for a bad
// value (hapi_dataset's parse*Arg); cfg->validate() checks the whole.
bool setScenarioOption(const std::string& key, const std::string& value, ScenarioConfig* cfg);

}  // namespace hapi_sim
