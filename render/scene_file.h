// Scene files: JSON, validated on load. Any unknown key, wrong type, missing file or value out of
// range is one lobe::Error naming the file, the key path (`objects[2].brdf.alpha_x`) and what was
// expected. The format is documented in docs/scene-format.md.
#pragma once

#include "render/scene_description.h"

#include <string>

namespace lobe {

SceneSpec loadSceneFile(const std::string& path);

// The same from JSON text; relative source paths resolve against `baseDir`; `name` is used in
// error messages.
SceneSpec parseScene(const std::string& jsonText, const std::string& baseDir,
                     const std::string& name);

}  // namespace lobe
