#include "core/interrupt.h"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstring>

namespace lobe {
namespace {

// Fixed storage the handler can read without allocating: a slot is claimed by setting `used`,
// filled, then published by `ready`; the handler unlinks every ready path.
constexpr int kSlots = 16;
constexpr size_t kPathMax = 4096;
struct Slot {
    std::atomic<bool> used{false};
    std::atomic<bool> ready{false};
    char path[kPathMax];
};
Slot g_slots[kSlots];

extern "C" void removeAndRaise(int signal) {
    for (Slot& s : g_slots)
        if (s.ready.load()) unlink(s.path);  // async-signal-safe
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

}  // namespace

void installInterruptCleanup() {
    std::signal(SIGINT, removeAndRaise);
    std::signal(SIGTERM, removeAndRaise);
}

RemovedOnInterrupt::RemovedOnInterrupt(const std::string& path) {
    if (path.size() >= kPathMax) return;
    for (int i = 0; i < kSlots; ++i) {
        bool expected = false;
        if (!g_slots[i].used.compare_exchange_strong(expected, true)) continue;
        std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
        g_slots[i].ready.store(true);
        slot_ = i;
        return;
    }
}

RemovedOnInterrupt::~RemovedOnInterrupt() {
    if (slot_ < 0) return;
    g_slots[slot_].ready.store(false);
    g_slots[slot_].used.store(false);
}

}  // namespace lobe
