// Internal to render/: the label keys of scene files (docs/scene-format.md, "Labels") — a
// source's "labels" and "label_table", and "kind": "segmentation" — checked against the label
// map when the scene is read. render/scene_file.cpp calls these and puts the key path in front
// of their lobe::Error messages.
#pragma once

#include "core/spectrum.h"
#include "volume/label_table.h"
#include "volume/labels.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <vector>

namespace lobe {

struct LabelSource {
    std::shared_ptr<const LabelMap> map;  // loaded once per process (volume/labels.h)
    LabelTable table;                     // empty when none is given or beside the map
};

// The map at `mapPath` (loaded and indexed once per process) and its table: `tableValue` when
// given — a file name (any format of volume/label_table.h, relative to baseDir) or an object
// {"37": "Hippocampus_L", "38": {"name": "Hippocampus_R", "color": "#rrggbb" or [r, g, b]}} —
// else MRIcron's MAP.txt/MAP.lut beside the map. Throws when the map is not a label map, the
// table cannot be read, or the table does not match the map (a label of the map it does not list).
LabelSource openLabelSource(const std::string& mapPath, const nlohmann::json* tableValue,
                            const std::string& baseDir);
// The same for a map already loaded (an array's, volume/labels.h): no table is looked for beside
// it when `mapPath` is empty.
LabelSource openLabelSource(std::shared_ptr<const LabelMap> map, const std::string& mapPath,
                            const nlohmann::json* tableValue, const std::string& baseDir);

// The label ids a "labels" value names: a number or name, or an array of them (and "all", the
// labels present, when allowAll). Throws for a label not present (naming the nearest present
// ones), a name in no table (naming the nearest names), a label given twice, an empty list.
std::vector<int> labelIdsOf(const nlohmann::json& value, const LabelSource& source, bool allowAll);

// The table's name of `id`, or "label N".
std::string labelName(const LabelSource& source, int id);
// The table's colour of `id` (sRGB bytes decoded, IEC 61966-2-1, and converted to the bands), or
// `fallback` when the table gives none.
Spectrum labelColour(const LabelSource& source, int id, const Spectrum& fallback);

}  // namespace lobe
