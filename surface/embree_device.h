// RAII owners of an Embree device and scene. Embree reports errors through a device callback
// that runs inside Embree's C code, where throwing is not allowed; the callback therefore only
// records the message (per thread), and check() — called after every API call that can fail —
// turns the recorded error into one lobe::Error on the calling thread. Flush-to-zero /
// denormals-are-zero, which Embree asks for, is set per thread by core's setFlushToZero().
#pragma once

#include <embree3/rtcore.h>

#include <string>

namespace lobe {

class EmbreeDevice {
public:
    // config: Embree's device configuration string ("" for defaults, e.g. "threads=1").
    explicit EmbreeDevice(const std::string& config = "");
    ~EmbreeDevice();
    EmbreeDevice(const EmbreeDevice&) = delete;
    EmbreeDevice& operator=(const EmbreeDevice&) = delete;
    EmbreeDevice(EmbreeDevice&& other) noexcept;
    EmbreeDevice& operator=(EmbreeDevice&& other) noexcept;

    RTCDevice get() const { return device_; }
    // Throws lobe::Error naming `what` if Embree recorded an error on this thread since the last
    // check.
    void check(const std::string& what) const;

private:
    RTCDevice device_ = nullptr;
};

class EmbreeScene {
public:
    explicit EmbreeScene(const EmbreeDevice& device);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;
    EmbreeScene(EmbreeScene&& other) noexcept;
    EmbreeScene& operator=(EmbreeScene&& other) noexcept;

    RTCScene get() const { return scene_; }
    // Attaches a geometry (committing it first), releases our reference, returns its ID.
    unsigned attach(RTCGeometry geometry);
    void commit();

private:
    const EmbreeDevice* device_ = nullptr;
    RTCScene scene_ = nullptr;
};

}  // namespace lobe
