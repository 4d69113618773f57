#include "core/embree_device.hpp"

#include <sys/resource.h>

#include <stdexcept>

#include "microbrdf/error.hpp"
#include "microbrdf/memory_budget.hpp"

namespace microbrdf::detail {

RTCDevice new_embree_device(const char* config, const std::string& who) {
  if (RTCDevice d = rtcNewDevice(config)) return d;
  const RTCError code = rtcGetDeviceError(nullptr);
  if (code == RTC_ERROR_UNKNOWN || code == RTC_ERROR_INVALID_ARGUMENT ||
      code == RTC_ERROR_INVALID_OPERATION || code == RTC_ERROR_UNSUPPORTED_CPU)
    throw std::runtime_error(who + ": Embree cannot create a device (error " +
                             std::to_string(int(code)) + ")");
  // RTC_ERROR_OUT_OF_MEMORY, or no code at all (the allocation failed before Embree could
  // record one): memory or address space is short.
  std::string limit;
  struct rlimit as {};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY)
    limit = "; the address-space limit (ulimit -v) is " + format_bytes(as.rlim_cur);
  throw OutOfMemory(who + ": out of memory or address space: Embree cannot create its device" +
                    limit + "; raise the limit or free memory");
}

}  // namespace microbrdf::detail
