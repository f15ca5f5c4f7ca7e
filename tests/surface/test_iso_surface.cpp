// Render-level tests of the two iso-surface methods on analytic volumes:
// - a linear ramp (the trilinear interpolant of a linear function is that function, so the plane
//   f = iso is hit exactly) under identity, anisotropic (1,1,2), flipped-rotated and sheared
//   transforms: hit distance within 1e-6 and the normal exact;
// - a sphere's distance field on a 32³ grid: the exact method against an independent reference
//   root of the trilinear interpolant (OpenVDB's BoxSampler, dense sampling + bisection,
//   surface_test_grids.h) within 1e-4 voxel, over a dense set of rays — axis rays on a half-voxel
//   lattice (so along voxel edges and faces and through corners), diagonal rays through lattice
//   points, grazing rays and random rays — with no missed hits; closeness to the true sphere and
//   its normal at looser tolerances (the sampled field's iso-surface is not exactly the sphere);
// - the same on an anisotropic (1,1,2) grid;
// - the mesh method's hit-distance and normal error against the exact method, measured and
//   reported (stdout and RecordProperty), asserted only loosely (< 1 voxel);
// - the scene: objects, depth-ordered hits, occlusion, errors for bad input.
#include "core/error.h"
#include "core/rng.h"
#include "surface/iso_exact.h"
#include "surface/iso_levelset.h"
#include "surface/iso_mesh.h"
#include "surface/surface_scene.h"
#include "surface_test_grids.h"

#include <gtest/gtest.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

namespace lobe {
namespace {

using test::makeGrid;
using test::referenceRoot;
using test::sampleIndex;

const double kIdentity[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const double kAniso[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 2}};

class OpenVdbInit : public ::testing::Environment {
public:
    void SetUp() override { openvdb::initialize(); }
};
const auto* const kOpenVdbEnv = ::testing::AddGlobalTestEnvironment(new OpenVdbInit);

Vec3 randomUnit(Rng& rng) {
    // Uniform on the sphere: z uniform in [−1,1], azimuth uniform (Archimedes).
    const double z = 2.0 * rng.uniform() - 1.0, phi = 2.0 * kPi * rng.uniform();
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

double angleDegrees(const Vec3& a, const Vec3& b) {
    const double c = std::max(-1.0, std::min(1.0, a.dot(b) / (a.length() * b.length())));
    return std::acos(c) * 180.0 / kPi;
}

SurfaceScene sceneOf(std::shared_ptr<const SurfaceGeometry> g) {
    SurfaceScene scene("threads=1");
    scene.add(std::move(g));
    scene.commit();
    return scene;
}

// ---------------------------------------------------------------------------------------------
// Linear ramp: f(x) = gw·x + b in world space, iso 0.

struct RampCase {
    const char* name;
    double linear[3][3];
};

// Identity, anisotropic, rotated with a flip, sheared: the maps the ramp tests run under.
const RampCase kRampCases[] = {
    {"identity", {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}},
    {"spacing 1,1,2", {{1, 0, 0}, {0, 1, 0}, {0, 0, 2}}},
    {"rotated+flipped", {{0, -1, 0}, {1, 0, 0}, {0, 0, -1.5}}},
    {"sheared", {{1, 0.25, 0}, {0, 0.75, 0.25}, {0.125, 0, 2}}},
};

// Rays from random points of a 16³ lattice in random directions: every ray whose crossing of the
// plane gw·x = c lies inside the stored lattice hits there (t to 1e-6) with the expected normal
// (to 1e-9) on object 0; at least 500 such rays.
void expectPlaneHits(const SurfaceScene& scene, const AffineMap& map, const Vec3& gw, double c,
                     const Vec3& expectedNormal, std::uint64_t stream) {
    Rng rng(42, stream);
    int tested = 0;
    for (int n = 0; n < 3000; ++n) {
        const Vec3 oIdx(2 + 11 * rng.uniform(), 2 + 11 * rng.uniform(), 2 + 11 * rng.uniform());
        Ray ray;
        ray.o = map.toWorld(oIdx);
        ray.d = randomUnit(rng);
        const double tStar = (c - gw.dot(ray.o)) / gw.dot(ray.d);
        if (!(tStar > 0.0)) continue;
        const Vec3 hIdx = map.toIndex(ray.at(tStar));
        if (hIdx.x < 1 || hIdx.y < 1 || hIdx.z < 1 || hIdx.x > 14 || hIdx.y > 14 || hIdx.z > 14)
            continue;  // the ramp holds only inside the stored lattice
        ++tested;
        const auto hit = scene.intersect(ray);
        ASSERT_TRUE(hit) << "ray " << n;
        EXPECT_NEAR(hit->t, tStar, 1e-6) << "ray " << n;
        EXPECT_NEAR(hit->normal.x, expectedNormal.x, 1e-9);
        EXPECT_NEAR(hit->normal.y, expectedNormal.y, 1e-9);
        EXPECT_NEAR(hit->normal.z, expectedNormal.z, 1e-9);
        EXPECT_EQ(hit->objectId, 0);
    }
    EXPECT_GT(tested, 500);
}

TEST(IsoExact, LinearRampHitsThePlaneExactlyUnderAffineTransforms) {
    // Dyadic slopes, matrices and origin: every voxel value is exact in float, so the stored
    // interpolant is exactly the ramp and its gradient exactly gw (up to double rounding).
    const Vec3 gw = Vec3(0.25, -0.5, 0.75);
    const double b = 1.25;
    const int dims[3] = {16, 16, 16};
    for (const RampCase& rc : kRampCases) {
        SCOPED_TRACE(rc.name);
        const Vec3 origin(3.0, -2.0, 5.0);
        auto grid = makeGrid(dims, rc.linear, origin, -1000.0f,
                             [&](const Vec3& x) { return gw.dot(x) + b; });
        // iso such that the plane passes through the grid's centre.
        const AffineMap map = AffineMap::fromTransform(grid->transform());
        const double iso = gw.dot(map.toWorld(Vec3(7.5, 7.5, 7.5))) + b;
        auto surface = std::make_shared<IsoExactSurface>(*grid, iso, rc.name);
        SurfaceScene scene = sceneOf(surface);
        const Vec3 expectedNormal = -gw / gw.length();  // −∇f: out of the region f > iso
        // gw·x + b = iso.
        expectPlaneHits(scene, map, gw, iso - b, expectedNormal, 1);
    }
}

// ---------------------------------------------------------------------------------------------
// Sphere distance field: f(x) = R − |x − c| (positive inside), iso 0, background −20 (no crossing
// at the grid's border, where f ≈ −5 jumps to −20).

constexpr double kRadius = 10.0;
const Vec3 kCentre(15.3, 15.6, 15.45);

openvdb::FloatGrid::Ptr sphereGrid(const double linear[3][3], const int dims[3]) {
    return makeGrid(dims, linear, Vec3(0.0), -20.0f,
                    [](const Vec3& x) { return kRadius - (x - kCentre).length(); });
}

// The dense ray set, in world space.
std::vector<Ray> sphereRays(const AffineMap& map, const int dims[3]) {
    std::vector<Ray> rays;
    const Vec3 lo = map.toWorld(Vec3(0.0)),
               hi = map.toWorld(Vec3(dims[0] - 1, dims[1] - 1, dims[2] - 1));
    const double span = (hi - lo).length();
    // Axis rays both ways on a half-voxel lattice of index positions: integer/integer lines run
    // along voxel edges through corners, integer/half lines along faces.
    for (int axis = 0; axis < 3; ++axis) {
        const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
        for (double p = 4.0; p <= dims[a1] - 5.0; p += 0.5)
            for (double q = 4.0; q <= dims[a2] - 5.0; q += 0.5)
                for (int sign : {1, -1}) {
                    Vec3 oIdx(0.0), dIdx(0.0);
                    oIdx[a1] = p;
                    oIdx[a2] = q;
                    oIdx[axis] = sign > 0 ? -3.0 : dims[axis] + 2.0;
                    dIdx[axis] = sign;
                    Ray r;
                    r.o = map.toWorld(oIdx);
                    r.d = normalized(map.toWorld(oIdx + dIdx) - r.o);
                    rays.push_back(r);
                }
    }
    // Diagonal rays through lattice points (voxel corners) in several directions.
    const Vec3 dirs[] = {Vec3(1, 1, 1),  Vec3(1, 1, 0),  Vec3(1, -1, 1),
                         Vec3(-1, 2, 0), Vec3(0, 1, -1), Vec3(2, 1, -1)};
    for (const Vec3& dIdx : dirs)
        for (int i = 6; i < dims[0] - 6; i += 2)
            for (int j = 6; j < dims[1] - 6; j += 2) {
                const Vec3 p = map.toWorld(Vec3(i, j, dims[2] / 2));
                Ray r;
                r.d = normalized(map.toWorld(dIdx) - map.toWorld(Vec3(0.0)));
                r.o = p - r.d * span;
                rays.push_back(r);
            }
    // Grazing rays: passing the true centre at R − δ, entering the interpolant's iso-surface at
    // shallow angles; and random rays from outside towards random interior points.
    Rng rng(2024, 5);
    for (double delta : {0.02, 0.05, 0.1, 0.3}) {
        for (int n = 0; n < 300; ++n) {
            const Vec3 d = randomUnit(rng);
            Vec3 side = normalized(d.cross(randomUnit(rng)));
            Ray r;
            r.d = d;
            r.o = kCentre + side * (kRadius - delta) - d * span;
            rays.push_back(r);
        }
    }
    for (int n = 0; n < 2000; ++n) {
        const Vec3 target =
            map.toWorld(Vec3(rng.uniform() * (dims[0] - 1), rng.uniform() * (dims[1] - 1),
                             rng.uniform() * (dims[2] - 1)));
        const Vec3 d = randomUnit(rng);
        Ray r;
        r.d = d;
        r.o = target - d * span;
        rays.push_back(r);
    }
    return rays;
}

struct ExactStats {
    int rays = 0, hits = 0, missed = 0, unresolvedByReference = 0;
    double maxErrVoxel = 0.0, maxSphereErr = 0.0, maxNormalDeg = 0.0, maxGradDeg = 0.0;
};

// Checks the exact method against the reference root on every ray; returns the statistics.
ExactStats checkExactAgainstReference(const openvdb::FloatGrid& grid, const SurfaceScene& scene,
                                      const std::vector<Ray>& rays, double sphereTolerance,
                                      double normalToleranceDeg) {
    const AffineMap map = AffineMap::fromTransform(grid.transform());
    ExactStats st;
    for (std::size_t n = 0; n < rays.size(); ++n) {
        const Ray& ray = rays[n];
        const Vec3 oIdx = map.toIndex(ray.o), dIdx = map.directionToIndex(ray.d);
        const double voxelsPerT = dIdx.length();
        const std::optional<double> ref = referenceRoot(grid, 0.0, oIdx, dIdx, 0.0, 200.0);
        const std::optional<SurfaceHit> hit = scene.intersect(ray);
        ++st.rays;
        if (ref && !hit) {
            ++st.missed;
            ADD_FAILURE() << "missed hit on ray " << n << " at t = " << *ref;
            continue;
        }
        if (!hit) continue;
        ++st.hits;
        const double fHit = sampleIndex(grid, map.toIndex(hit->position));
        if (!ref || hit->t < *ref - 1e-4 / voxelsPerT) {
            // An earlier root than the reference found: legitimate only if it is a root (a pair of
            // roots closer than the reference's sampling, near a tangent).
            ++st.unresolvedByReference;
            EXPECT_NEAR(fHit, 0.0, 1e-5) << "spurious hit on ray " << n << " at t = " << hit->t;
        } else {
            const double errVoxel = std::abs(hit->t - *ref) * voxelsPerT;
            st.maxErrVoxel = std::max(st.maxErrVoxel, errVoxel);
            EXPECT_LT(errVoxel, 1e-4)
                << "ray " << n << ": t = " << hit->t << ", reference " << *ref;
        }
        // Closeness to the true sphere and its normal (looser: sampling error of the field).
        const double sphereErr = std::abs((hit->position - kCentre).length() - kRadius);
        st.maxSphereErr = std::max(st.maxSphereErr, sphereErr);
        EXPECT_LT(sphereErr, sphereTolerance) << "ray " << n;
        const double nDeg = angleDegrees(hit->normal, hit->position - kCentre);
        st.maxNormalDeg = std::max(st.maxNormalDeg, nDeg);
        EXPECT_LT(nDeg, normalToleranceDeg) << "ray " << n;
        EXPECT_NEAR(hit->normal.length(), 1.0, 1e-12);
        // The normal is −∇ of the interpolant: compare with central differences of BoxSampler in
        // world space, away from cell faces (where the trilinear gradient is discontinuous).
        const Vec3 u = map.toIndex(hit->position);
        const double h = 1e-5;
        bool nearFace = false;
        for (int a = 0; a < 3; ++a) {
            const double frac = u[a] - std::floor(u[a]);
            nearFace = nearFace || frac < 1e-3 || frac > 1 - 1e-3;
        }
        if (!nearFace) {
            Vec3 gw;
            for (int a = 0; a < 3; ++a) {
                Vec3 e(0.0);
                e[a] = h;
                gw[a] = (sampleIndex(grid, map.toIndex(hit->position + e)) -
                         sampleIndex(grid, map.toIndex(hit->position - e))) /
                        (2 * h);
            }
            const double gDeg = angleDegrees(hit->normal, -gw);
            st.maxGradDeg = std::max(st.maxGradDeg, gDeg);
            EXPECT_LT(gDeg, 0.5) << "ray " << n;  // float BoxSampler over 2e-5 limits this
        }
    }
    return st;
}

void report(const char* what, const ExactStats& st) {
    std::printf(
        "[%s] rays %d, hits %d, missed %d, extra roots the reference skipped %d, "
        "max |t − t_ref| %.3g voxel, max ||x − c| − R| %.4f, max normal vs sphere %.3f°, "
        "max normal vs −∇(BoxSampler) %.4f°\n",
        what, st.rays, st.hits, st.missed, st.unresolvedByReference, st.maxErrVoxel,
        st.maxSphereErr, st.maxNormalDeg, st.maxGradDeg);
    ::testing::Test::RecordProperty("max_t_error_voxel", std::to_string(st.maxErrVoxel));
    ::testing::Test::RecordProperty("max_sphere_error", std::to_string(st.maxSphereErr));
}

TEST(IsoExact, SphereDistanceFieldNoMissesAndRootsWithin1e4Voxel) {
    const int dims[3] = {32, 32, 32};
    auto grid = sphereGrid(kIdentity, dims);
    auto surface = std::make_shared<IsoExactSurface>(*grid, 0.0, "sphere");
    EXPECT_GT(surface->brickCount(), 0u);
    EXPECT_LT(surface->brickCount(), surface->candidateBrickCount());  // some bricks skipped
    SurfaceScene scene = sceneOf(surface);
    const std::vector<Ray> rays = sphereRays(AffineMap::fromTransform(grid->transform()), dims);
    // Sampling error of |x| by trilinear interpolation ≈ h²/(8R) ≈ 0.0125 voxel: 0.03 allowed.
    // Normal: each component of the trilinear gradient interpolates edge differences, i.e. the
    // true derivative at edge midpoints up to √(0.5² + 0.5²) = 0.707 voxel away across the
    // cell; on a sphere the normal turns by distance/R, so up to 0.707/10 rad = 4.05°: 5° allowed.
    const ExactStats st = checkExactAgainstReference(*grid, scene, rays, 0.03, 5.0);
    report("exact, sphere 32³", st);
    EXPECT_EQ(st.missed, 0);
    EXPECT_GT(st.hits, 3000);
}

// Two stored voxels 1e5 apart span 1e15 cells: the exact method's table is refused by its size
// before it is allocated (it threw std::bad_alloc), and the error points to the mesh method.
TEST(IsoExact, TwoVoxelsFarApartAreRefusedByTheTablesSize) {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->tree().setValue(openvdb::Coord(0, 0, 0), 1.0f);
    grid->tree().setValue(openvdb::Coord(100000, 100000, 100000), 1.0f);
    try {
        IsoExactSurface surface(*grid, 0.5, "far.vdb");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("far.vdb: the exact iso-surface's table"),
                  std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("\"method\": \"mesh\""), std::string::npos)
            << e.what();
    }
}

TEST(IsoExact, SphereOnAnisotropicGrid) {
    const int dims[3] = {32, 32, 16};  // world z spacing 2: 0 … 30
    auto grid = sphereGrid(kAniso, dims);
    auto surface = std::make_shared<IsoExactSurface>(*grid, 0.0, "sphere 1,1,2");
    SurfaceScene scene = sceneOf(surface);
    const std::vector<Ray> rays = sphereRays(AffineMap::fromTransform(grid->transform()), dims);
    // Spacing 2 along z quadruples the sampling error there: h²/(8R) = 0.05. Normal: edge
    // midpoints up to √(0.5² + 1²) = 1.118 world units away: 1.118/10 rad = 6.41°: 7.5° allowed.
    const ExactStats st = checkExactAgainstReference(*grid, scene, rays, 0.12, 7.5);
    report("exact, sphere 32x32x16 spacing 1,1,2", st);
    EXPECT_EQ(st.missed, 0);
    EXPECT_GT(st.hits, 2000);
}

// ---------------------------------------------------------------------------------------------
// Mesh method: error measured against the exact method, reported, asserted loosely.

void measureMesh(const double linear[3][3], const int dims[3], const char* label) {
    auto grid = sphereGrid(linear, dims);
    auto exact = std::make_shared<IsoExactSurface>(*grid, 0.0, "sphere");
    auto mesh = std::make_shared<IsoMeshSurface>(*grid, 0.0, "sphere");
    ASSERT_GT(mesh->quadCount(), 100u);
    SurfaceScene exactScene = sceneOf(exact), meshScene = sceneOf(mesh);
    const AffineMap map = AffineMap::fromTransform(grid->transform());
    const std::vector<Ray> rays = sphereRays(map, dims);
    int both = 0, onlyExact = 0, onlyMesh = 0;
    double sumErr = 0, sumErr2 = 0, maxErr = 0, sumDeg = 0, maxDeg = 0, maxSphere = 0;
    double maxSurfaceDistance = 0;
    for (const Ray& ray : rays) {
        const auto e = exactScene.intersect(ray);
        const auto m = meshScene.intersect(ray);
        if (e && !m) {
            // The mesh is inscribed in the interpolant's surface (its vertices lie on cell edges
            // at the crossings, its facets cut inside), so it loses rays near the silhouette:
            // allowed only for rays passing within a voxel of the sphere's outline.
            ++onlyExact;
            const double lineDistance = (kCentre - ray.o).cross(ray.d).length();
            EXPECT_GT(lineDistance, kRadius - 1.0) << "mesh missed a ray far from the silhouette";
        }
        if (m && !e) ++onlyMesh;
        if (!e || !m) continue;
        ++both;
        const double err = std::abs(m->t - e->t) * map.directionToIndex(ray.d).length();
        sumErr += err;
        sumErr2 += err * err;
        maxErr = std::max(maxErr, err);
        // Distance of the mesh hit from the interpolant's iso-surface, first order: |f| / |∇f|
        // (world units; a voxel is ≥ 1 world unit in both grids).
        const Vec3 u = map.toIndex(m->position);
        Vec3 gw;
        for (int a = 0; a < 3; ++a) {
            Vec3 h(0.0);
            h[a] = 1e-4;
            gw[a] = (sampleIndex(*grid, map.toIndex(m->position + h)) -
                     sampleIndex(*grid, map.toIndex(m->position - h))) /
                    2e-4;
        }
        const double surfaceDistance = std::abs(sampleIndex(*grid, u)) / gw.length();
        maxSurfaceDistance = std::max(maxSurfaceDistance, surfaceDistance);
        EXPECT_LT(surfaceDistance, 1.0);  // loose: the mesh is a different surface, not a wrong one
        const double deg = angleDegrees(m->normal, e->normal);
        sumDeg += deg;
        maxDeg = std::max(maxDeg, deg);
        maxSphere = std::max(maxSphere, std::abs((m->position - kCentre).length() - kRadius));
        EXPECT_NEAR(m->normal.length(), 1.0, 1e-12);
    }
    std::printf(
        "[mesh vs exact, %s] %zu quads (%zu triangles), rays %zu: both hit %d, only exact "
        "%d, only mesh %d; |Δt| mean %.4f rms %.4f max %.4f voxel; distance to the "
        "interpolant's surface max %.4f; normal Δ mean %.3f° max %.3f°; max ||x − c| − R| "
        "%.4f\n",
        label, mesh->quadCount(), mesh->triangleCount(), rays.size(), both, onlyExact, onlyMesh,
        sumErr / both, std::sqrt(sumErr2 / both), maxErr, maxSurfaceDistance, sumDeg / both, maxDeg,
        maxSphere);
    ::testing::Test::RecordProperty("mesh_mean_t_error_voxel", std::to_string(sumErr / both));
    ::testing::Test::RecordProperty("mesh_max_t_error_voxel", std::to_string(maxErr));
    ::testing::Test::RecordProperty("mesh_max_normal_error_deg", std::to_string(maxDeg));
    ::testing::Test::RecordProperty("mesh_rays_missed", std::to_string(onlyExact));
    EXPECT_EQ(onlyMesh, 0);     // the inscribed mesh never sticks out of the exact surface
    EXPECT_LT(maxSphere, 1.0);  // the mesh lies in world space, within a voxel of the sphere
}

TEST(IsoMesh, SphereErrorAgainstExactIsMeasured) {
    const int dims[3] = {32, 32, 32};
    measureMesh(kIdentity, dims, "sphere 32³");
}

TEST(IsoMesh, AnisotropicGridMeshIsInWorldSpace) {
    const int dims[3] = {32, 32, 16};
    measureMesh(kAniso, dims, "sphere 32x32x16 spacing 1,1,2");
}

// A closed mesh lets no ray through: rays aimed exactly at every vertex and at points along
// every edge (where two triangles or two quads meet), from outside and from inside, all hit
// no later than the point they aim at (Embree's robust traversal, embree_device.cpp).
TEST(IsoMesh, ClosedMeshLetsNoRayThroughEdgesOrVertices) {
    const int dims[3] = {32, 32, 32};
    auto grid = sphereGrid(kIdentity, dims);
    auto mesh = std::make_shared<IsoMeshSurface>(*grid, 0.0, "sphere");
    SurfaceScene scene = sceneOf(mesh);
    const std::vector<float>& v = mesh->vertices();
    const std::vector<std::uint32_t>& q = mesh->quads();
    const auto vertex = [&](std::uint32_t i) { return Vec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]); };
    std::vector<Vec3> targets;
    for (std::size_t i = 0; i < v.size() / 3; ++i) targets.push_back(vertex(std::uint32_t(i)));
    for (std::size_t f = 0; f < q.size(); f += 4)
        for (int e = 0; e < 4; ++e) {
            const Vec3 a = vertex(q[f + e]), b = vertex(q[f + (e + 1) % 4]);
            for (double s : {0.25, 0.5, 0.75}) targets.push_back(a + (b - a) * s);
        }
    // The quads' diagonals, shared by their two triangles: Embree splits a quad into
    // (v0, v1, v3) and (v2, v3, v1).
    for (std::size_t f = 0; f < q.size(); f += 4) {
        const Vec3 a = vertex(q[f + 1]), c = vertex(q[f + 3]);
        for (double s : {0.25, 0.5, 0.75}) targets.push_back(a + (c - a) * s);
    }
    Rng rng(7, 3);
    int rays = 0, leaks = 0;
    for (const Vec3& p : targets) {
        const Vec3 out = normalized(p - kCentre);
        // From outside along a tilted outward direction, and from near the centre.
        const Vec3 tilt = normalized(out + randomUnit(rng) * 0.5);
        Ray fromOutside;
        fromOutside.o = p + tilt * 40.0;
        fromOutside.d = -tilt;
        Ray fromInside;
        fromInside.o = kCentre + randomUnit(rng) * 0.5;
        fromInside.d = normalized(p - fromInside.o);
        for (const Ray& r : {fromOutside, fromInside}) {
            ++rays;
            const double reach = (p - r.o).length();
            const auto hit = scene.intersect(r);
            if (!hit || hit->t > reach + 1e-4) {
                ++leaks;
                if (leaks <= 5)
                    std::printf(
                        "  leak: o (%.9g %.9g %.9g) d (%.9g %.9g %.9g) reach %.6f hit %s t %.6f\n",
                        r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, reach, hit ? "yes" : "no",
                        hit ? hit->t : 0.0);
            }
        }
    }
    std::printf("[mesh leak test] %zu quads, %d rays at vertices and edges, %d passed through\n",
                mesh->quadCount(), rays, leaks);
    EXPECT_GT(rays, 20000);
    EXPECT_EQ(leaks, 0);
}

// ---------------------------------------------------------------------------------------------
// Level sets (iso_levelset.h): analytic distance fields used as they are, and density grids
// rebuilt as level sets.

// −φ as a grid (values, tiles and background negated): the field the exact reference solves.
openvdb::FloatGrid::Ptr negated(const openvdb::FloatGrid& phi) {
    openvdb::FloatGrid::Ptr g = phi.deepCopy();
    for (auto it = g->beginValueAll(); it; ++it) it.setValue(-*it);
    g->tree().root().setBackground(-phi.background(), /*updateChildNodes=*/false);
    return g;
}

openvdb::FloatGrid::Ptr asLevelSet(openvdb::FloatGrid::Ptr g) {
    g->setGridClass(openvdb::GRID_LEVEL_SET);
    return g;
}

TEST(LevelSet, PlaneUnderAffineTransformsIsHitExactly) {
    // φ(x) = gw·x + b − level: a plane, exact under trilinear interpolation (dyadic values).
    const Vec3 gw = Vec3(0.25, -0.5, 0.75);
    const int dims[3] = {16, 16, 16};
    for (const RampCase& rc : kRampCases) {
        SCOPED_TRACE(rc.name);
        const Vec3 origin(3.0, -2.0, 5.0);
        auto probe = makeGrid(dims, rc.linear, origin, 0.0f, [](const Vec3&) { return 0.0; });
        const AffineMap map = AffineMap::fromTransform(probe->transform());
        const double level = gw.dot(map.toWorld(Vec3(7.5, 7.5, 7.5)));
        auto phi = asLevelSet(makeGrid(dims, rc.linear, origin, 1000.0f,
                                       [&](const Vec3& x) { return gw.dot(x) - level; }));
        auto surface = std::make_shared<LevelSetSurface>(phi, rc.name);
        SurfaceScene scene = sceneOf(surface);
        const Vec3 expectedNormal = gw / gw.length();  // ∇φ: out of the object (φ < 0)
        expectPlaneHits(scene, map, gw, level, expectedNormal, 2);
    }
}

// OpenVDB's own narrow-band sphere (3 voxels each side, tiles inside and outside): the band's
// blocks are the only primitives, and every ray of the dense set (edges, corners, grazing) finds
// the root of φ's interpolant that the independent reference finds.
TEST(LevelSet, NarrowBandSphereNoMissesAndRootsWithin1e4Voxel) {
    const int dims[3] = {32, 32, 32};
    auto phi = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
        float(kRadius), openvdb::Vec3f(float(kCentre.x), float(kCentre.y), float(kCentre.z)), 1.0f,
        3.0f);
    auto surface = std::make_shared<LevelSetSurface>(phi, "sphere");
    EXPECT_GT(surface->blockCount(), 0u);
    EXPECT_LE(surface->blockCount(), phi->tree().leafCount() * 8);
    SurfaceScene scene = sceneOf(surface);
    const std::vector<Ray> rays = sphereRays(AffineMap::fromTransform(phi->transform()), dims);
    const ExactStats st = checkExactAgainstReference(*negated(*phi), scene, rays, 0.03, 5.0);
    report("level set, OpenVDB narrow-band sphere", st);
    EXPECT_EQ(st.missed, 0);
    EXPECT_GT(st.hits, 3000);
}

// A torus's distance field on a sheared grid: roots against the reference, and on the torus.
TEST(LevelSet, TorusOnAShearedGrid) {
    const double sheared[3][3] = {{1, 0.25, 0}, {0, 0.75, 0.25}, {0.125, 0, 1.5}};
    const int dims[3] = {40, 40, 28};
    const double big = 8.0, small = 3.5;
    const Vec3 c(21.0, 16.0, 22.0);
    const auto torus = [&](const Vec3& x) {
        const Vec3 p = x - c;
        const double ring = std::sqrt(p.x * p.x + p.y * p.y) - big;
        return std::sqrt(ring * ring + p.z * p.z) - small;
    };
    auto phi = asLevelSet(makeGrid(dims, sheared, Vec3(0.0), 100.0f, torus));
    auto surface = std::make_shared<LevelSetSurface>(phi, "torus");
    SurfaceScene scene = sceneOf(surface);
    const AffineMap map = AffineMap::fromTransform(phi->transform());
    auto reference = negated(*phi);
    Rng rng(11, 4);
    int hits = 0, missed = 0;
    double maxErr = 0.0, maxTorus = 0.0;
    for (int n = 0; n < 4000; ++n) {
        // Towards a random point near the torus's tube, from 60 units away.
        const double a = 2 * kPi * rng.uniform();
        const Vec3 aim = c + Vec3(big * std::cos(a), big * std::sin(a), 0.0) +
                         randomUnit(rng) * (small * rng.uniform());
        Ray ray;
        ray.d = randomUnit(rng);
        ray.o = aim - ray.d * 60.0;
        const Vec3 oIdx = map.toIndex(ray.o), dIdx = map.directionToIndex(ray.d);
        const auto ref = referenceRoot(*reference, 0.0, oIdx, dIdx, 0.0, 200.0);
        const auto hit = scene.intersect(ray);
        if (ref && !hit) {
            ++missed;
            continue;
        }
        if (!hit) continue;
        ++hits;
        ASSERT_TRUE(ref) << "a hit where the reference finds none, ray " << n;
        const double err = std::abs(hit->t - *ref) * dIdx.length();
        maxErr = std::max(maxErr, err);
        EXPECT_LT(err, 1e-4) << "ray " << n;
        maxTorus = std::max(maxTorus, std::abs(torus(hit->position)));
    }
    std::printf(
        "[level set, torus on a sheared grid] rays 4000, hits %d, missed %d, max |t − t_ref| "
        "%.3g voxel, max |φ_torus(hit)| %.4f\n",
        hits, missed, maxErr, maxTorus);
    EXPECT_EQ(missed, 0);
    EXPECT_GT(hits, 2000);
    EXPECT_LT(maxTorus, 0.1);  // interpolation error of the sampled distance, not a wrong root
}

// A density rebuilt as a level set (levelSetRebuild): negative inside, where the density is
// above iso; the surface close to the density's own iso-surface; for a shell, the cavity is
// outside (normals point into it). An isotropic rebuild at half the voxel size is closer.
TEST(LevelSet, FromDensitySignAccuracyAndVoxelSize) {
    const int dims[3] = {32, 32, 32};
    auto density = sphereGrid(kIdentity, dims);  // R − |x − c|: positive inside
    auto surface = LevelSetSurface::fromDensity(*density, 0.0, LevelSetOptions{}, "sphere");
    const auto phiAt = [&](const Vec3& x) {
        return sampleIndex(surface->levelSet(), surface->map().toIndex(x));
    };
    EXPECT_LT(phiAt(kCentre + Vec3(0, 0, kRadius - 1.5)), 0.0);
    EXPECT_GT(phiAt(kCentre + Vec3(0, 0, kRadius + 1.5)), 0.0);
    LevelSetOptions fine;
    fine.voxelSize = 0.5;
    auto fineSurface = LevelSetSurface::fromDensity(*density, 0.0, fine, "sphere");
    EXPECT_GT(fineSurface->blockCount(), surface->blockCount());
    const AffineMap map = AffineMap::fromTransform(density->transform());
    const std::vector<Ray> rays = sphereRays(map, dims);
    auto exactScene = sceneOf(std::make_shared<IsoExactSurface>(*density, 0.0, "sphere"));
    double maxErr[2] = {0, 0};
    int index = 0;
    for (const auto& s : {surface, fineSurface}) {
        SurfaceScene scene = sceneOf(s);
        int both = 0;
        for (const Ray& ray : rays) {
            const auto e = exactScene.intersect(ray);
            const auto h = scene.intersect(ray);
            const double lineDistance = (kCentre - ray.o).cross(ray.d).length();
            if (e && lineDistance < kRadius - 1.0) {
                EXPECT_TRUE(h) << "a ray well inside the outline missed";
            }
            if (!e || !h) continue;
            ++both;
            maxErr[index] =
                std::max(maxErr[index], std::abs((h->position - kCentre).length() - kRadius));
            EXPECT_GT(h->normal.dot(h->position - kCentre), 0.0);  // outwards
        }
        EXPECT_GT(both, 3000);
        ++index;
    }
    // The exact method's own distance to the sphere is 0.025 (IsoExact above), the mesh's 0.064.
    std::printf(
        "[level set from density, sphere 32³] max ||x − c| − R|: %.4f (source voxel), "
        "%.4f (voxel 0.5)\n",
        maxErr[0], maxErr[1]);
    EXPECT_LT(maxErr[0], 0.15);
    EXPECT_LT(maxErr[1], 0.15);

    // A shell 6 < r < 10: from the centre, the first hit is the inner wall, facing the centre.
    auto shell = makeGrid(dims, kIdentity, Vec3(0.0), -20.0f, [](const Vec3& x) {
        const double r = (x - kCentre).length();
        return std::min(r - 6.0, kRadius - r);
    });
    SurfaceScene shellScene =
        sceneOf(LevelSetSurface::fromDensity(*shell, 0.0, LevelSetOptions{}, "shell"));
    Rng rng(5, 5);
    for (int n = 0; n < 200; ++n) {
        Ray ray;
        ray.o = kCentre;
        ray.d = randomUnit(rng);
        const auto hit = shellScene.intersect(ray);
        ASSERT_TRUE(hit);
        EXPECT_NEAR(hit->t, 6.0, 0.25);
        EXPECT_LT(hit->normal.dot(ray.d), 0.0);  // facing the cavity
    }
}

TEST(LevelSet, BadOptionsAreErrors) {
    const int dims[3] = {8, 8, 8};
    auto density = sphereGrid(kIdentity, dims);
    LevelSetOptions narrow;
    narrow.halfWidth = 0.5;
    EXPECT_THROW(LevelSetSurface::fromDensity(*density, 0.0, narrow, "g"), Error);
    LevelSetOptions negative;
    negative.voxelSize = -1.0;
    EXPECT_THROW(LevelSetSurface::fromDensity(*density, 0.0, negative, "g"), Error);
    EXPECT_THROW(LevelSetSurface::fromDensity(*density, std::nan(""), LevelSetOptions{}, "g"),
                 Error);
    LevelSetOptions tiny;
    tiny.voxelSize = 1e-6;  // a 32³ box at 1e-6: 3e22 voxels
    const int bigDims[3] = {32, 32, 32};
    auto big = sphereGrid(kIdentity, bigDims);
    try {
        LevelSetSurface::fromDensity(*big, 0.0, tiny, "big.vdb");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("big.vdb"), std::string::npos) << e.what();
    }
}

// ---------------------------------------------------------------------------------------------
// Scene: two objects, hits in depth order, occlusion.

TEST(SurfaceScene, TwoObjectsHitsInDepthOrderAndOcclusion) {
    const int dims[3] = {32, 32, 32};
    auto gridA = sphereGrid(kIdentity, dims);
    // The second sphere: the same field, its grid translated by +40 along x.
    auto gridB = makeGrid(dims, kIdentity, Vec3(40, 0, 0), -20.0f, [](const Vec3& x) {
        return kRadius - (x - kCentre - Vec3(40, 0, 0)).length();
    });
    SurfaceScene scene("threads=1");
    EXPECT_EQ(scene.add(std::make_shared<IsoExactSurface>(*gridA, 0.0)), 0);
    EXPECT_EQ(scene.add(std::make_shared<IsoMeshSurface>(*gridB, 0.0)), 1);
    EXPECT_THROW(scene.intersect(Ray{}), Error);  // not committed yet
    scene.commit();
    EXPECT_THROW(scene.add(std::make_shared<IsoExactSurface>(*gridA, 0.0)), Error);

    // Along +x through both centres: enter/leave A near x = 15.3 ∓ 10, then B near 55.3 ∓ 10.
    Ray ray;
    ray.o = Vec3(-10, kCentre.y, kCentre.z);
    ray.d = Vec3(1, 0, 0);
    const std::vector<SurfaceHit> hits = scene.allHits(ray);
    ASSERT_EQ(hits.size(), 4u);
    const double expectX[4] = {kCentre.x - kRadius, kCentre.x + kRadius, kCentre.x + 40 - kRadius,
                               kCentre.x + 40 + kRadius};
    const int expectObject[4] = {0, 0, 1, 1};
    for (int i = 0; i < 4; ++i) {
        EXPECT_NEAR(hits[i].position.x, expectX[i], 0.6);
        EXPECT_EQ(hits[i].objectId, expectObject[i]);
        if (i > 0) {
            EXPECT_GT(hits[i].t, hits[i - 1].t);
        }
        // Outward normals: −x when entering a sphere, +x when leaving.
        EXPECT_NEAR(hits[i].normal.x, (i % 2 == 0) ? -1.0 : 1.0, 0.05);
    }
    EXPECT_TRUE(scene.occluded(ray));
    Ray shortRay = ray;
    shortRay.tMax = hits[0].t - 0.01;
    EXPECT_FALSE(scene.occluded(shortRay));
    EXPECT_FALSE(scene.intersect(shortRay));
    Ray miss = ray;
    miss.o.y += 30;
    EXPECT_FALSE(scene.occluded(miss));
    EXPECT_FALSE(scene.intersect(miss));
}

// ---------------------------------------------------------------------------------------------
// Bad input and empty input.

TEST(IsoSurfaces, BadInputIsAnError) {
    const int dims[3] = {8, 8, 8};
    auto grid = sphereGrid(kIdentity, dims);
    EXPECT_THROW(IsoExactSurface(*grid, std::nan(""), "g"), Error);
    EXPECT_THROW(IsoMeshSurface(*grid, std::nan(""), "g"), Error);
    grid->tree().setValue(openvdb::Coord(3, 3, 3), std::nanf(""));
    EXPECT_THROW(IsoExactSurface(*grid, 0.0, "g"), Error);
    auto frustum = openvdb::FloatGrid::create(0.0f);
    frustum->setTransform(openvdb::math::Transform::createFrustumTransform(
        openvdb::BBoxd(openvdb::Vec3d(0), openvdb::Vec3d(10)), 0.5, 10.0, 1.0));
    frustum->tree().setValue(openvdb::Coord(1, 1, 1), 1.0f);
    EXPECT_THROW(IsoExactSurface(*frustum, 0.5, "frustum"), Error);
    EXPECT_THROW(IsoMeshSurface(*frustum, 0.5, "frustum"), Error);
}

TEST(IsoSurfaces, EmptyAndConstantGridsHaveNoSurface) {
    auto empty = openvdb::FloatGrid::create(0.0f);
    auto exact = std::make_shared<IsoExactSurface>(*empty, 0.5);
    EXPECT_EQ(exact->brickCount(), 0u);
    auto mesh = std::make_shared<IsoMeshSurface>(*empty, 0.5);
    EXPECT_EQ(mesh->quadCount(), 0u);
    SurfaceScene scene("threads=1");
    scene.add(exact);
    scene.add(mesh);
    scene.commit();
    Ray ray;
    ray.o = Vec3(-5, 0.5, 0.5);
    ray.d = Vec3(1, 0, 0);
    EXPECT_FALSE(scene.intersect(ray));
    // A constant grid above iso everywhere it is stored, background below: the surface is the
    // boundary of the stored block (the interpolant falls from 1 to 0 over one cell).
    auto block = openvdb::FloatGrid::create(0.0f);
    block->tree().fill(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(15)), 1.0f);
    SurfaceScene s2 = sceneOf(std::make_shared<IsoExactSurface>(*block, 0.5));
    ray.o = Vec3(-5, 7.3, 7.6);
    const auto hit = s2.intersect(ray);
    ASSERT_TRUE(hit);
    // Along x the interpolant is 0 at x = −1 and 1 at x = 0: crosses 0.5 at x = −0.5.
    EXPECT_NEAR(hit->position.x, -0.5, 1e-9);
    EXPECT_NEAR(hit->normal.x, -1.0, 1e-9);
}

}  // namespace
}  // namespace lobe
