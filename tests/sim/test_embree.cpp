// Embree errors: the device's error callback records them, device creation
// and geometry-buffer failures throw a message that names Embree's error, and
// a good scene raises none.
#include <gtest/gtest.h>

#include <functional>
#include <stdexcept>
#include <string>

#include "embree_device.hpp"
#include "scene.hpp"
#include "sim_test_util.hpp"

namespace sonarfusion::sim {
namespace {

std::string thrownMessage(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "";
}

TEST(Embree, InvalidDeviceConfigFailsWithAClearMessage) {
    const std::string what = thrownMessage([] { EmbreeDevice device("threads=notanumber"); });
    EXPECT_NE(what.find("cannot create a device with config 'threads=notanumber'"), std::string::npos) << what;
    EXPECT_NE(what.find("RTC_ERROR_"), std::string::npos) << what;

    const std::string scene_what =
        thrownMessage([] { const Scene scene({test::flatPlane(20.0)}, {MeshSpec{}}, 1.5, "threads=notanumber"); });
    EXPECT_NE(scene_what.find("threads=notanumber"), std::string::npos) << scene_what;
}

// A memory monitor that refuses every allocation makes rtcSetNewGeometryBuffer
// fail the way a real out-of-memory does: it returns null.
bool refuseAllocations(void* /*user*/, ssize_t bytes, bool /*post*/) { return bytes <= 0; }

TEST(Embree, NullGeometryBufferThrowsWithEmbreesErrorAndIsRecorded) {
    EmbreeDevice device;
    EXPECT_EQ(device.errorCount(), 0u);
    rtcSetDeviceMemoryMonitorFunction(device.get(), refuseAllocations, nullptr);
    RTCGeometry geometry = rtcNewGeometry(device.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
    ASSERT_NE(geometry, nullptr);
    const std::string what = thrownMessage([&] {
        (void)device.newGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 100,
                                       "vertex buffer of mesh 0");
    });
    rtcReleaseGeometry(geometry);
    EXPECT_NE(what.find("cannot allocate the vertex buffer of mesh 0 (100 items)"), std::string::npos) << what;
    EXPECT_NE(what.find("RTC_ERROR_OUT_OF_MEMORY"), std::string::npos) << what;
    ASSERT_EQ(device.errorCount(), 1u);
    EXPECT_EQ(device.errors()[0].code, RTC_ERROR_OUT_OF_MEMORY);
    EXPECT_FALSE(device.errors()[0].message.empty());
}

TEST(Embree, CallbackRecordsErrorsOfInvalidCalls) {
    EmbreeDevice device;
    RTCScene scene = rtcNewScene(device.get());
    RTCGeometry geometry = rtcNewGeometry(device.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcAttachGeometryByID(scene, geometry, 7);
    rtcAttachGeometryByID(scene, geometry, 7);  // the same geometry and id twice
    rtcReleaseGeometry(geometry);
    rtcReleaseScene(scene);
    ASSERT_GE(device.errorCount(), 1u);
    EXPECT_EQ(device.errors()[0].code, RTC_ERROR_INVALID_OPERATION);
    EXPECT_FALSE(device.errors()[0].message.empty());
    const std::string what = thrownMessage([&] { device.check("attach"); });
    EXPECT_NE(what.find("Embree error in attach: RTC_ERROR_INVALID_OPERATION"), std::string::npos) << what;
}

TEST(Embree, GoodSceneRaisesNoError) {
    const Scene scene({test::flatPlane(20.0), test::box(4.0, 0.0, 19.5, 0.5, 0.5, 0.5)}, {MeshSpec{}, MeshSpec{}}, 1.5);
    EXPECT_EQ(scene.embreeErrorCount(), 0u);
    EXPECT_EQ(scene.triangleCount(), 14u);
}

}  // namespace
}  // namespace sonarfusion::sim
