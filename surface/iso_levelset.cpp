// An iso-surface as an OpenVDB narrow-band level set; see iso_levelset.h.
#include "surface/iso_levelset.h"

#include "core/error.h"
#include "core/memory.h"
#include "surface/trilinear_cell.h"
#include "surface/user_geometry.h"

#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/LevelSetFilter.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace lobe {
namespace {

constexpr int kCells = BrickCells::kCells;
constexpr int kPoints = BrickCells::kPoints;

using Accessor = openvdb::FloatGrid::ConstUnsafeAccessor;

// The 8 corners of the cell at p of f = −φ, in trilinear_cell.h order.
inline void corners(const Accessor& acc, const openvdb::Coord& p, double c[8]) {
    for (int i = 0; i < 8; ++i)
        c[i] = -double(acc.getValue(p.offsetBy(i & 1, (i >> 1) & 1, (i >> 2) & 1)));
}

}  // namespace

std::shared_ptr<LevelSetSurface> LevelSetSurface::fromDensity(const openvdb::FloatGrid& density,
                                                              double iso,
                                                              const LevelSetOptions& options,
                                                              const std::string& name) {
    if (!std::isfinite(iso)) throw Error(name + ": iso value must be finite");
    AffineMap::fromGrid(density, name);  // refuses a non-affine transform
    if (!(options.halfWidth >= 1.0) || !std::isfinite(options.halfWidth))
        throw Error(name + ": the level set's half width must be at least 1 voxel");
    if (options.smoothIterations < 0 || options.smoothIterations > 1000)
        throw Error(name + ": the level set's smoothing iterations must be 0 … 1000");
    if (!(options.voxelSize >= 0.0) || !std::isfinite(options.voxelSize))
        throw Error(name + ": the level set's voxel size must be finite and not negative");
    // Built in the density transform's own world: the density's world scale (tiny voxels,
    // volume/grid_world.h) divides the voxel size asked for in scene units and is the level set's.
    const double worldScale = gridWorldScale(density);
    openvdb::math::Transform::Ptr xform = density.transform().copy();
    double voxelSize = options.voxelSize / worldScale;
    if (voxelSize == 0.0 && options.smoothIterations > 0 && !xform->hasUniformScale()) {
        // OpenVDB's level-set filters need cubic voxels: the source's smallest side.
        const openvdb::Vec3d side = xform->voxelSize();
        voxelSize = std::min(side.x(), std::min(side.y(), side.z()));
    }
    if (voxelSize > 0.0) {
        // Refused before the rebuild allocates: the band of the source's bounding box, resampled.
        const openvdb::CoordBBox box = density.evalActiveVoxelBoundingBox();
        const openvdb::BBoxd world = density.transform().indexToWorld(box);
        const openvdb::Vec3d extent = world.extents() / voxelSize;
        checkFits(extent.x() * extent.y() * extent.z() * sizeof(float),
                  name + ": a level set at voxel size " + std::to_string(voxelSize * worldScale));
        xform = openvdb::math::Transform::createLinearTransform(voxelSize);
    }
    // The distance: unsigned, to the iso-surface's mesh (volumeToMesh at adaptivity 0, as the
    // mesh method), in a band of ±halfWidth voxels.
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(density, points, triangles, quads, iso, 0.0);
    if (quads.empty() && triangles.empty())
        throw Error(name + ": no surface at iso " + std::to_string(iso) +
                    " (every voxel is on one side of it)");
    openvdb::FloatGrid::Ptr phi = openvdb::tools::meshToUnsignedDistanceField<openvdb::FloatGrid>(
        *xform, points, triangles, quads, static_cast<float>(options.halfWidth));
    // The sign: from the density itself (negative where its interpolant is above iso), not from
    // the mesh's connectivity: levelSetRebuild's meshToVolume calls every region the outside
    // cannot reach "inside", which fills the cavity of a shell (the skull's cranial cavity) and
    // loses its inner wall. Then the band's signs fill the tiles and inactive voxels.
    {
        openvdb::tree::LeafManager<openvdb::FloatTree> leaves(phi->tree());
        const openvdb::math::Transform& from = phi->transform();
        leaves.foreach ([&](openvdb::FloatTree::LeafNodeType& leaf, std::size_t) {
            const auto acc = density.getConstUnsafeAccessor();
            for (auto v = leaf.beginValueOn(); v; ++v) {
                const openvdb::Vec3d u =
                    density.transform().worldToIndex(from.indexToWorld(v.getCoord()));
                if (openvdb::tools::BoxSampler::sample(acc, u) > iso) v.setValue(-*v);
            }
        });
    }
    openvdb::tools::signedFloodFill(phi->tree());
    phi->setGridClass(openvdb::GRID_LEVEL_SET);
    if (worldScale != 1.0) phi->insertMeta(kMetaWorldScale, openvdb::DoubleMetadata(worldScale));
    if (options.smoothIterations > 0) {
        openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*phi);
        for (int i = 0; i < options.smoothIterations; ++i) filter.meanCurvature();
    }
    return std::make_shared<LevelSetSurface>(phi, name);
}

LevelSetSurface::LevelSetSurface(openvdb::FloatGrid::ConstPtr levelSet, const std::string& name)
    : phi_(std::move(levelSet)), map_(AffineMap::fromGrid(*phi_, name)) {
    const openvdb::FloatTree& tree = phi_->tree();
    if (!std::isfinite(tree.background()))
        throw Error(name + ": the level set's background value is not finite");
    // Candidate blocks: each leaf's own and the 7 behind it, since a cell reads the +1 lattice
    // points and so can start one voxel before a leaf (a band of at least a voxel keeps every
    // corner of a sign-changing cell inside the leaves).
    std::vector<openvdb::Coord> candidates;
    candidates.reserve(tree.leafCount() * 8);
    for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
        const openvdb::Coord o = leaf->origin();
        for (int c = 0; c < 8; ++c)
            candidates.push_back(
                o.offsetBy((c & 1) ? -kCells : 0, (c & 2) ? -kCells : 0, (c & 4) ? -kCells : 0));
    }
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());

    std::vector<BrickCells> classes(candidates.size());
    std::vector<char> nonFinite(candidates.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, candidates.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          Accessor acc(tree);
                          float values[BrickCells::kValues];
                          for (std::size_t b = range.begin(); b != range.end(); ++b) {
                              float* v = values;
                              bool finite = true;
                              for (int k = 0; k < kPoints; ++k)
                                  for (int j = 0; j < kPoints; ++j)
                                      for (int i = 0; i < kPoints; ++i) {
                                          const float x =
                                              -acc.getValue(candidates[b].offsetBy(i, j, k));
                                          finite = finite && std::isfinite(x);
                                          *v++ = x;
                                      }
                              nonFinite[b] = !finite;
                              if (finite) classes[b] = BrickCells::classify(values, 0.0);
                          }
                      });
    if (std::find(nonFinite.begin(), nonFinite.end(), 1) != nonFinite.end())
        throw Error(name + ": the level set holds non-finite (NaN or Inf) values");
    for (std::size_t b = 0; b < candidates.size(); ++b) {
        if (!classes[b].anyStraddles()) continue;
        origins_.push_back(candidates[b]);
        cells_.push_back(classes[b]);
        bounds_.push_back(brickWorldBounds(map_, candidates[b], classes[b]));
    }
}

std::size_t LevelSetSurface::memoryBytes() const {
    return phi_->tree().memUsage() + origins_.size() * sizeof(openvdb::Coord) +
           cells_.size() * sizeof(BrickCells) + bounds_.size() * sizeof(bounds_[0]);
}

bool LevelSetSurface::intersectPrimitive(unsigned block, const Vec3& o, const Vec3& d, double tMin,
                                         double tMax, double& t) const {
    return intersectPrimitive(block, WalkRay(o, d), tMin, tMax, t);
}

bool LevelSetSurface::intersectPrimitive(unsigned block, const WalkRay& ray, double tMin,
                                         double tMax, double& t) const {
    const Accessor acc(phi_->tree());
    const openvdb::Coord& origin = origins_[block];
    const auto cellCorners = [&](int lx, int ly, int lz, double c[8]) {
        corners(acc, origin.offsetBy(lx, ly, lz), c);
    };
    return firstRootInBrick(origin, cells_[block], 0.0, ray, tMin, tMax, cellCorners, t);
}

Vec3 LevelSetSurface::worldGradient(unsigned block, const Vec3& u) const {
    const openvdb::Coord cell = cellInBrick(origins_[block], u);
    const Accessor acc(phi_->tree());
    double c[8];
    corners(acc, cell, c);
    const Vec3 local(u.x - cell.x(), u.y - cell.y(), u.z - cell.z());
    return map_.gradientToWorld(trilinearGradient(c, local));
}

SurfaceHit LevelSetSurface::shade(const Ray& ray, double t, unsigned primId) const {
    return user_geometry::shadeByGradient(
        ray, t, primId, [&](const Vec3& x) { return worldGradient(primId, map_.toIndex(x)); });
}

RTCGeometry LevelSetSurface::createGeometry(RTCDevice device) const {
    return user_geometry::create(device, this, origins_.size());
}

}  // namespace lobe
