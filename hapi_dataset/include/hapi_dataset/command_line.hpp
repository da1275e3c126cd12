// The command lines of the recording tools (asl_to_bag, make_sim_bag,
// make_globe_bag): `--key value` pairs, -h/--help, numbers checked the same
// way everywhere. ROS-free.
#pragma once

#include <functional>
#include <string>

namespace hapi_dataset {

// Calls handle(key, value) for each `--key value` pair of argv[1..]. Calls
// usage(message), which must not return (it exits), for -h/--help ("help"),
// for a key without a value, and with the message of a
// std::invalid_argument that handle throws (the parse*Arg functions below).
void forEachOption(int argc, char** argv, const std::function<void(const std::string&)>& usage,
                   const std::function<void(const std::string& key, const std::string& value)>& handle);

// The finite number `value` of option `key`; throws std::invalid_argument
// with the message to print otherwise.
double parseNumberArg(const std::string& key, const std::string& value);
// An integer in [lo, hi]; throws std::invalid_argument otherwise.
long long parseIntegerArg(const std::string& key, const std::string& value, long long lo, long long hi);
// "0" or "1"; throws std::invalid_argument otherwise.
bool parseFlagArg(const std::string& key, const std::string& value);

}  // namespace hapi_dataset
