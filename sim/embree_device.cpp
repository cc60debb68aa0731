#include "embree_device.hpp"

#include <cstdio>
#include <stdexcept>

namespace sonarfusion::sim {

const char* embreeErrorName(RTCError code) {
    switch (code) {
        case RTC_ERROR_NONE: return "RTC_ERROR_NONE";
        case RTC_ERROR_UNKNOWN: return "RTC_ERROR_UNKNOWN";
        case RTC_ERROR_INVALID_ARGUMENT: return "RTC_ERROR_INVALID_ARGUMENT";
        case RTC_ERROR_INVALID_OPERATION: return "RTC_ERROR_INVALID_OPERATION";
        case RTC_ERROR_OUT_OF_MEMORY: return "RTC_ERROR_OUT_OF_MEMORY";
        case RTC_ERROR_UNSUPPORTED_CPU: return "RTC_ERROR_UNSUPPORTED_CPU";
        case RTC_ERROR_CANCELLED: return "RTC_ERROR_CANCELLED";
    }
    return "RTC_ERROR (unknown code)";
}

EmbreeDevice::EmbreeDevice(const std::string& config) {
    device_ = rtcNewDevice(config.empty() ? nullptr : config.c_str());
    if (!device_) {
        // No callback can be registered before the device exists: Embree keeps
        // the creation error for rtcGetDeviceError(nullptr).
        const RTCError code = rtcGetDeviceError(nullptr);
        throw std::runtime_error("Embree: cannot create a device with config '" + config + "': " +
                                 embreeErrorName(code) + " (error " + std::to_string(static_cast<int>(code)) + ")");
    }
    rtcSetDeviceErrorFunction(device_, &EmbreeDevice::onError, this);
}

EmbreeDevice::~EmbreeDevice() {
    if (device_) {
        rtcSetDeviceErrorFunction(device_, nullptr, nullptr);
        rtcReleaseDevice(device_);
    }
}

void EmbreeDevice::onError(void* self, RTCError code, const char* message) {
    auto* d = static_cast<EmbreeDevice*>(self);
    const std::string text = message ? message : "";
    std::fprintf(stderr, "sf-sim: Embree error %s: %s\n", embreeErrorName(code), text.c_str());
    const std::lock_guard<std::mutex> lock(d->mutex_);
    ++d->count_;
    if (d->errors_.size() < kMaxKept) d->errors_.push_back({code, text});
}

std::vector<EmbreeDevice::Error> EmbreeDevice::errors() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return errors_;
}

std::size_t EmbreeDevice::errorCount() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return count_;
}

std::string EmbreeDevice::describeLast(RTCError code) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    std::string s = embreeErrorName(code);
    if (!errors_.empty() && !errors_.back().message.empty()) s += ": " + errors_.back().message;
    return s;
}

void* EmbreeDevice::newGeometryBuffer(RTCGeometry geometry, RTCBufferType type, RTCFormat format,
                                      std::size_t byte_stride, std::size_t count, const std::string& what) {
    void* buffer = rtcSetNewGeometryBuffer(geometry, type, 0, format, byte_stride, count);
    if (!buffer) {
        const RTCError code = rtcGetDeviceError(device_);
        throw std::runtime_error("Embree: cannot allocate the " + what + " (" + std::to_string(count) +
                                 " items): " + describeLast(code == RTC_ERROR_NONE ? RTC_ERROR_UNKNOWN : code));
    }
    return buffer;
}

void EmbreeDevice::check(const std::string& what) const {
    const RTCError code = rtcGetDeviceError(device_);
    if (code != RTC_ERROR_NONE) throw std::runtime_error("Embree error in " + what + ": " + describeLast(code));
}

}  // namespace sonarfusion::sim
