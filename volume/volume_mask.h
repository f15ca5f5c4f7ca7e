// A mask: a second volume deciding where an object exists (docs/scene-format.md, "Mask"). An
// object with a mask keeps the points where the mask's value, trilinearly interpolated, is above
// `iso` (inverted: at or below it) — the T1 shown only inside a brain mask, the skull only outside
// it. Volumes drop the samples the mask refuses (volume/volume_marcher.h), surfaces the hits
// (surface/surface_scene.h, SurfaceScene::setMask).
//
// Label sets (`"labels": [...]`) give the mask as their anti-aliased indicator (volume/labels.h,
// labelSurfaceField) with iso 0.5: render/scene.cpp builds that grid.
#pragma once

#include "core/math.h"

#include <openvdb/openvdb.h>

namespace lobe {

class VolumeMask {
public:
    // `grid` maps index → scene world (the object's transform applied).
    VolumeMask(openvdb::FloatGrid::ConstPtr grid, double iso, bool invert);

    // Whether the object exists at world point x. Thread-safe (reads the tree without an
    // accessor).
    bool keeps(const Vec3& x) const;

    double iso() const { return iso_; }
    bool inverted() const { return invert_; }

private:
    openvdb::FloatGrid::ConstPtr grid_;
    double iso_ = 0.5;
    bool invert_ = false;
};

}  // namespace lobe
