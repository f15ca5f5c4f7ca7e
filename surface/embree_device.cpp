// Embree device and scene owners; see embree_device.h for the error-handling design.
#include "surface/embree_device.h"

#include "core/error.h"
#include "core/memory.h"

#include <utility>

namespace lobe {
namespace {

// The last error Embree reported on this thread (its callback runs on the thread that made the
// failing call).
thread_local std::string tLastEmbreeMessage;

void recordEmbreeError(void* /*userPtr*/, RTCError code, const char* message) {
    tLastEmbreeMessage = "Embree error " + std::to_string(static_cast<int>(code)) + ": " +
                         (message ? message : "(no message)");
}

}  // namespace

EmbreeDevice::EmbreeDevice(const std::string& config) {
    device_ = rtcNewDevice(config.empty() ? nullptr : config.c_str());
    if (!device_) {
        const RTCError code = rtcGetDeviceError(nullptr);
        // Out of memory (RTC_ERROR_OUT_OF_MEMORY), e.g. its thread stacks under ulimit -v: said
        // so, with the limit that binds.
        if (code == RTC_ERROR_OUT_OF_MEMORY)
            throw Error("Embree cannot create a device: " + outOfMemoryText());
        throw Error("Embree: cannot create a device (config '" + config + "', error " +
                    std::to_string(static_cast<int>(code)) + ")");
    }
    rtcSetDeviceErrorFunction(device_, recordEmbreeError, nullptr);
}

EmbreeDevice::~EmbreeDevice() {
    if (device_) rtcReleaseDevice(device_);
}

EmbreeDevice::EmbreeDevice(EmbreeDevice&& other) noexcept
    : device_(std::exchange(other.device_, nullptr)) {}

EmbreeDevice& EmbreeDevice::operator=(EmbreeDevice&& other) noexcept {
    if (this != &other) {
        if (device_) rtcReleaseDevice(device_);
        device_ = std::exchange(other.device_, nullptr);
    }
    return *this;
}

void EmbreeDevice::check(const std::string& what) const {
    const RTCError code = rtcGetDeviceError(device_);
    if (code == RTC_ERROR_NONE) return;
    std::string message = tLastEmbreeMessage.empty()
                              ? "Embree error " + std::to_string(static_cast<int>(code))
                              : tLastEmbreeMessage;
    tLastEmbreeMessage.clear();
    if (code == RTC_ERROR_OUT_OF_MEMORY) message = "Embree: " + outOfMemoryText();
    throw Error(what + ": " + message);
}

EmbreeScene::EmbreeScene(const EmbreeDevice& device) : device_(&device) {
    scene_ = rtcNewScene(device.get());
    device.check("creating an Embree scene");
    // Robust traversal: rays through voxel corners and edges and grazing rays must not slip
    // between brick bounds or between the two triangles of a quad.
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
}

EmbreeScene::~EmbreeScene() {
    if (scene_) rtcReleaseScene(scene_);
}

EmbreeScene::EmbreeScene(EmbreeScene&& other) noexcept
    : device_(other.device_), scene_(std::exchange(other.scene_, nullptr)) {}

EmbreeScene& EmbreeScene::operator=(EmbreeScene&& other) noexcept {
    if (this != &other) {
        if (scene_) rtcReleaseScene(scene_);
        device_ = other.device_;
        scene_ = std::exchange(other.scene_, nullptr);
    }
    return *this;
}

unsigned EmbreeScene::attach(RTCGeometry geometry) {
    rtcCommitGeometry(geometry);
    const unsigned id = rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    device_->check("attaching a geometry to the Embree scene");
    return id;
}

void EmbreeScene::commit() {
    rtcCommitScene(scene_);
    device_->check("building the Embree scene (BVH)");
}

}  // namespace lobe
