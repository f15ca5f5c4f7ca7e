// Scene text parsed in tests: the message of the lobe::Error it raises. Shared by
// tests/render/test_scene_file.cpp and test_framing.cpp.
#pragma once

#include "core/error.h"
#include "render/scene_file.h"

#include <string>

namespace lobe::test {

// The folder scene paths in test texts are relative to.
inline const std::string kSceneBase = std::string(LOBE_SOURCE_DIR) + "/tests/render";

// parseScene's error for `text`, or "" when it parses.
inline std::string errorOf(const std::string& text) {
    try {
        parseScene(text, kSceneBase, "scene.json");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace lobe::test
