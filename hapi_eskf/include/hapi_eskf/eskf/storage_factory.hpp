// The covariance storage of the ES-EKF named by the settings (backend cpu |
// cuda, covariance_update dense | partitioned, precision), sized by the
// filter's pose block (filterPoseDim: the motion model's rows plus the
// frame-error rows). The storages themselves (covariance/) know nothing of
// the filter; this is where the filter's settings choose one.
#pragma once

#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/settings.hpp"

#include <memory>
#include <string>

namespace hapi_eskf {

// The backend named in settings, with the pose block of its motion_model;
// nullptr (and *error set) when it cannot be
// created, e.g. CUDA not compiled in or no device.
std::unique_ptr<CovarianceBackend> makeBackend(const EskfSettings& s, int descriptor_length, std::string* error);

// True when the CUDA backend is compiled in and CUDA device `device` (the
// cuda_device setting) is usable. *why names the device and either describes
// it or says why it cannot be used.
bool cudaBackendAvailable(int device, std::string* why);

// True when the CUDA backend of the settings (max_landmarks, motion_model,
// precision, cuda_device) fits in the device's free memory with descriptors
// of up to `descriptor_length` bytes. Otherwise false, and *why states the
// memory needed, free and total (or why CUDA is unusable).
bool cudaPoolFits(const EskfSettings& s, int descriptor_length, std::string* why);

}  // namespace hapi_eskf
