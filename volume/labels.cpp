// Label maps: index, masks and anti-aliased indicators (labels.h).
#include "volume/labels.h"

#include "core/error.h"
#include "volume/gaussian_blur.h"
#include "volume/grid_world.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <set>

namespace lobe {

const LabelInfo* LabelMap::find(int id) const {
    const auto it = labels.find(id);
    return it == labels.end() ? nullptr : &it->second;
}

std::vector<int> LabelMap::nearestPresent(int id, int count) const {
    std::vector<int> ids;
    for (const auto& [label, info] : labels) ids.push_back(label);
    std::stable_sort(ids.begin(), ids.end(), [id](int a, int b) {
        return std::llabs(std::int64_t(a) - id) < std::llabs(std::int64_t(b) - id);
    });
    if (int(ids.size()) > count) ids.resize(size_t(count));
    return ids;
}

openvdb::CoordBBox LabelMap::boxOf(const std::vector<int>& ids) const {
    openvdb::CoordBBox box;
    for (int id : ids)
        if (const LabelInfo* info = find(id)) box.expand(info->box);
    return box;
}

LabelMap indexLabelMap(std::shared_ptr<const Volume> volume) {
    LabelMap map;
    map.path = volume->sourcePath;
    map.volume = volume;
    // Every stored value, tiles by their boxes: zeros are the background (not stored, or stored
    // inactive), everything else a label.
    for (auto it = volume->grid->tree().cbeginValueAll(); it; ++it) {
        const float v = *it;
        if (v == 0.0f) continue;
        openvdb::CoordBBox box;
        it.getBoundingBox(box);
        if (v != std::floor(v) || std::abs(v) > 2147483647.0f) {
            const openvdb::Coord c = box.min();
            char value[64];
            std::snprintf(value, sizeof value, "%.9g", double(v) / volume->valueScale);
            throw Error(volume->sourcePath + ": not a label map: voxel (" + std::to_string(c.x()) +
                        ", " + std::to_string(c.y()) + ", " + std::to_string(c.z()) + ") holds " +
                        value +
                        ", not a whole number (labels are whole numbers; is this an "
                        "intensity image or a probability map?)");
        }
        LabelInfo& info = map.labels[int(v)];
        info.id = int(v);
        info.voxels += std::int64_t(box.volume());
        info.box.expand(box);
    }
    return map;
}

std::shared_ptr<const LabelMap> loadLabelMap(const std::string& path) {
    static std::mutex mutex;
    static std::map<std::string, std::shared_ptr<const LabelMap>> maps;
    static std::map<std::string, std::shared_ptr<std::once_flag>> flags;
    std::shared_ptr<std::once_flag> flag;
    {
        std::lock_guard<std::mutex> lock(mutex);
        const auto it = maps.find(path);
        if (it != maps.end()) return it->second;
        auto& f = flags[path];
        if (!f) f = std::make_shared<std::once_flag>();
        flag = f;
    }
    // One load per path even when several threads ask at once; a failed load is retried (and
    // fails again with the same message) by the next caller.
    std::call_once(*flag, [&] {
        auto volume = std::make_shared<const Volume>(loadVolume(path));
        auto map = std::make_shared<const LabelMap>(indexLabelMap(volume));
        std::lock_guard<std::mutex> lock(mutex);
        maps[path] = map;
    });
    std::lock_guard<std::mutex> lock(mutex);
    return maps.at(path);
}

std::shared_ptr<const LabelMap> loadLabelMap(const VolumeArray& array) {
    auto volume = std::make_shared<const Volume>(loadArray(array));
    return std::make_shared<const LabelMap>(indexLabelMap(volume));
}

namespace {

// The grid holding `values` (dims n, x fastest, first voxel at `lo`) with the map's transform;
// voxels of `inside` (same layout) active, values ≤ 0 not stored.
openvdb::FloatGrid::Ptr gridOf(const LabelMap& map, const std::vector<float>& values,
                               const std::vector<unsigned char>& inside,
                               const std::array<int, 3>& n, const openvdb::Coord& lo) {
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    grid->setTransform(map.volume->grid->transform().copy());
    if (const auto scale = map.volume->grid->getMetadata<openvdb::DoubleMetadata>(kMetaWorldScale))
        grid->insertMeta(kMetaWorldScale, *scale);  // tiny voxels (volume/grid_world.h)
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    auto acc = grid->getAccessor();
    for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j)
            for (int i = 0; i < n[0]; ++i) {
                const size_t at = (size_t(k) * n[1] + j) * n[0] + i;
                const openvdb::Coord c = lo + openvdb::Coord(i, j, k);
                if (inside[at])
                    acc.setValueOn(c, values[at]);
                else if (values[at] > 0.0f)
                    acc.setValueOff(c, values[at]);
            }
    return grid;
}

std::vector<unsigned char> insideOf(const LabelMap& map, const std::vector<int>& ids,
                                    const std::array<int, 3>& n, const openvdb::Coord& lo) {
    const std::set<float> wanted(ids.begin(), ids.end());
    std::vector<unsigned char> inside(size_t(n[0]) * n[1] * n[2], 0);
    auto acc = map.volume->grid->getConstAccessor();
    for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j)
            for (int i = 0; i < n[0]; ++i) {
                const float v = acc.getValue(lo + openvdb::Coord(i, j, k));
                if (v != 0.0f && wanted.count(v)) inside[(size_t(k) * n[1] + j) * n[0] + i] = 1;
            }
    return inside;
}

}  // namespace

openvdb::FloatGrid::Ptr labelMask(const LabelMap& map, const std::vector<int>& ids) {
    const openvdb::CoordBBox box = map.boxOf(ids);
    if (box.empty()) throw Error(map.path + ": none of the labels asked for is in the map");
    const std::array<int, 3> n{box.dim().x(), box.dim().y(), box.dim().z()};
    const std::vector<unsigned char> inside = insideOf(map, ids, n, box.min());
    std::vector<float> values(inside.begin(), inside.end());
    return gridOf(map, values, inside, n, box.min());
}

openvdb::FloatGrid::Ptr labelSurfaceField(const LabelMap& map, const std::vector<int>& ids,
                                          double sigmaVoxels) {
    openvdb::CoordBBox box = map.boxOf(ids);
    if (box.empty()) throw Error(map.path + ": none of the labels asked for is in the map");
    // The blur's reach (4σ, gaussian_blur.cpp) and one more voxel, so the 0.5 level closes
    // inside the box and every cell around S's outermost voxels has its corners.
    box.expand(int(std::ceil(4.0 * sigmaVoxels)) + 1);
    const std::array<int, 3> n{box.dim().x(), box.dim().y(), box.dim().z()};
    const std::vector<unsigned char> inside = insideOf(map, ids, n, box.min());
    std::vector<float> values(inside.begin(), inside.end());
    if (sigmaVoxels > 0.0) gaussianBlurDense(values, n, {sigmaVoxels, sigmaVoxels, sigmaVoxels});
    return gridOf(map, values, inside, n, box.min());
}

}  // namespace lobe
