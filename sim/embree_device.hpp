// An Embree 3 device that reports its errors. As Embree's own tutorials do,
// an error callback is registered with rtcSetDeviceErrorFunction as soon as
// the device exists: every error Embree raises on it (from any thread) is
// written to stderr and recorded here, so a failure names Embree's own
// message instead of surfacing later as a null buffer or an empty scene.
#pragma once

#include <embree3/rtcore.h>

#include <cstddef>
#include <mutex>
#include <string>
#include <vector>

namespace sonarfusion::sim {

// "RTC_ERROR_OUT_OF_MEMORY" etc.
[[nodiscard]] const char* embreeErrorName(RTCError code);

class EmbreeDevice {
public:
    struct Error {
        RTCError code = RTC_ERROR_NONE;
        std::string message;
    };

    // config: Embree's device configuration string ("" = Embree's defaults,
    // e.g. "threads=1,verbose=1"). Throws std::runtime_error naming the config
    // and Embree's error code when Embree refuses to create the device.
    explicit EmbreeDevice(const std::string& config = "");
    ~EmbreeDevice();
    EmbreeDevice(const EmbreeDevice&) = delete;
    EmbreeDevice& operator=(const EmbreeDevice&) = delete;

    [[nodiscard]] RTCDevice get() const { return device_; }

    // Errors the callback has seen, oldest first (the first kMaxKept; count() has them all).
    [[nodiscard]] std::vector<Error> errors() const;
    [[nodiscard]] std::size_t errorCount() const;

    // rtcSetNewGeometryBuffer, checked: a null buffer throws
    // std::runtime_error "Embree: cannot allocate the <what> (<count> items):
    // <error name>: <Embree's message>".
    [[nodiscard]] void* newGeometryBuffer(RTCGeometry geometry, RTCBufferType type, RTCFormat format,
                                          std::size_t byte_stride, std::size_t count, const std::string& what);

    // Throws std::runtime_error naming `what` if Embree has an error pending
    // on this device (rtcGetDeviceError), with the last recorded message.
    void check(const std::string& what) const;

    static constexpr std::size_t kMaxKept = 16;

private:
    static void onError(void* self, RTCError code, const char* message);
    [[nodiscard]] std::string describeLast(RTCError code) const;

    RTCDevice device_ = nullptr;
    mutable std::mutex mutex_;
    std::vector<Error> errors_;
    std::size_t count_ = 0;
};

}  // namespace sonarfusion::sim
