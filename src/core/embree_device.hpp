// Creating an Embree device, with a message a user can act on when it fails. Embree fails to
// create a device mostly when memory or address space is short (it reserves memory up front,
// so a `ulimit -v` of a few hundred megabytes is enough to refuse it).
#pragma once

#include <embree3/rtcore.h>

#include <string>

namespace microbrdf::detail {

/// rtcNewDevice(config); on failure throws OutOfMemory (microbrdf/error.hpp) saying that
/// memory or address space ran out, with the address-space limit (ulimit -v) when one is set,
/// or std::runtime_error for Embree's other errors. `who` names what needed the device.
RTCDevice new_embree_device(const char* config, const std::string& who);

}  // namespace microbrdf::detail
