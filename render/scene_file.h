// Scene files: JSON, validated on load. Any unknown key, wrong type, missing file or value out of
// range is one lobe::Error naming the file, the key path (`objects[2].brdf.alpha_x`) and what was
// expected. The format is documented in docs/scene-format.md.
#pragma once

#include "render/scene_description.h"

#include <map>
#include <memory>
#include <string>

namespace lobe {

SceneSpec loadSceneFile(const std::string& path);

// In-memory volumes by name: a source {"array": NAME} in place of "path" (the Python module,
// docs/python.md). Scene files have none, so "array" in a file is an error.
using SceneArrays = std::map<std::string, std::shared_ptr<const VolumeArray>>;

// The same from JSON text; relative source paths resolve against `baseDir`; `name` is used in
// error messages; `arrays` are the in-memory sources the text may name.
SceneSpec parseScene(const std::string& jsonText, const std::string& baseDir,
                     const std::string& name, const SceneArrays* arrays = nullptr);

}  // namespace lobe
