#include "render/framing.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace lobe {

void WorldBox::grow(const Vec3& p) {
    lo = Vec3(std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z));
    hi = Vec3(std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z));
}

void WorldBox::grow(const WorldBox& b) {
    if (b.empty()) return;
    grow(b.lo);
    grow(b.hi);
}

namespace {

Vec3 corner(const WorldBox& b, int c) {
    return Vec3((c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z);
}

// The camera's orthonormal frame as PinholeCamera builds it (core/camera.cpp).
struct Basis {
    Vec3 forward, right, up;
};
Basis basisOf(const Vec3& forward, const Vec3& up) {
    Basis b;
    b.forward = normalized(forward);
    const Vec3 right = b.forward.cross(up);
    if (!(right.length() > 1e-9)) throw Error("the up vector is parallel to the view direction");
    b.right = normalized(right);
    b.up = b.right.cross(b.forward);
    return b;
}

std::string fmt(double x) {
    if (std::abs(x) < 5e-10) x = 0.0;  // no "-0" or 1e-17 noise in printed numbers
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", x);
    return buf;
}

std::string vec(const Vec3& v) { return "[" + fmt(v.x) + ", " + fmt(v.y) + ", " + fmt(v.z) + "]"; }

}  // namespace

ViewDirection viewDirection(const std::string& view, double azimuthDeg, double elevationDeg) {
    if (view == "anterior") return {Vec3(0, 1, 0), Vec3(0, 0, 1)};
    if (view == "posterior") return {Vec3(0, -1, 0), Vec3(0, 0, 1)};
    if (view == "right") return {Vec3(1, 0, 0), Vec3(0, 0, 1)};
    if (view == "left") return {Vec3(-1, 0, 0), Vec3(0, 0, 1)};
    if (view == "superior") return {Vec3(0, 0, 1), Vec3(0, 1, 0)};
    if (view == "inferior") return {Vec3(0, 0, -1), Vec3(0, 1, 0)};
    if (!view.empty())
        throw Error("unknown view '" + view +
                    "' (anterior, posterior, left, right, superior or inferior)");
    const double az = radians(azimuthDeg), el = radians(elevationDeg);
    const Vec3 horizontal(std::sin(az), std::cos(az), 0.0);
    if (std::abs(elevationDeg) >= 90.0)
        return {Vec3(0, 0, elevationDeg > 0 ? 1.0 : -1.0), horizontal};
    return {horizontal * std::cos(el) + Vec3(0, 0, std::sin(el)), Vec3(0, 0, 1)};
}

FittedCamera fitCamera(const WorldBox& box, const ViewDirection& dir, double vfovDeg, double aspect,
                       double margin, const std::string& method) {
    if (box.empty()) throw Error("the objects have no active voxel: nothing to fit the camera to");
    const Basis b = basisOf(-dir.toCamera, dir.up);
    const double tV = std::tan(radians(vfovDeg) * 0.5) / margin;
    const double tH = tV * aspect;
    const Vec3 c = box.center();
    double d = 0.0;
    if (method == "sphere") {
        // The cone of half angle α = atan(t) around the view axis touches a sphere of radius ρ
        // at distance ρ / sin α.
        const double rho = (box.hi - box.lo).length() * 0.5;
        const double t = std::min(tV, tH);
        d = rho * std::sqrt(1.0 + t * t) / t;
    } else {
        // A corner at lateral offsets (x, y) and depth z beyond the target projects inside the
        // frame iff |x| ≤ (d + z)·tH and |y| ≤ (d + z)·tV.
        for (int k = 0; k < 8; ++k) {
            const Vec3 q = corner(box, k) - c;
            const double z = q.dot(b.forward);
            d = std::max({d, std::abs(q.dot(b.right)) / tH - z, std::abs(q.dot(b.up)) / tV - z});
        }
    }
    if (!(d > 0.0) || !std::isfinite(d))
        throw Error("the objects' box is a single point: no distance frames it");
    FittedCamera out;
    out.target = c;
    out.position = c - b.forward * d;
    out.up = dir.up;
    out.distance = d;
    return out;
}

double cropStretch(const CropWindow& crop) { return (crop.x1 - crop.x0) / (crop.y1 - crop.y0); }

CropWindow zoomCrop(const ZoomSpec& zoom, const Vec3& position, const Vec3& target, const Vec3& up,
                    double vfovDeg, double aspect) {
    const Basis b = basisOf(target - position, up);
    const double tV = std::tan(radians(vfovDeg) * 0.5), tH = tV * aspect;
    // (u, v) of a world point in the full view (core/camera.cpp's generateRay, inverted).
    const auto project = [&](const Vec3& p, double& u, double& v) {
        const Vec3 q = p - position;
        const double z = q.dot(b.forward);
        if (!(z > 0.0)) throw Error("the point " + vec(p) + " is behind the camera");
        u = 0.5 * (1.0 + q.dot(b.right) / (z * tH));
        v = 0.5 * (1.0 - q.dot(b.up) / (z * tV));
        return z;
    };
    double cu = 0.0, cv = 0.0, extent = 0.0;
    if (zoom.kind == ZoomSpec::Kind::Point) {
        const double z = project(zoom.center, cu, cv);
        extent = zoom.size / (2.0 * z * std::min(tH, tV));
    } else {
        double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
        for (int k = 0; k < 8; ++k) {
            double u, v;
            project(corner(WorldBox{zoom.lo, zoom.hi}, k), u, v);
            u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
        }
        cu = 0.5 * (u0 + u1), cv = 0.5 * (v0 + v1);
        extent = std::max(u1 - u0, v1 - v0) * zoom.margin;
    }
    if (!(cu >= 0.0 && cu <= 1.0 && cv >= 0.0 && cv <= 1.0))
        throw Error("the zoom's centre is outside the view (at " + fmt(cu) + ", " + fmt(cv) +
                    " of the image)");
    if (!(extent > 0.0)) throw Error("the zoom region has no extent in the image");
    if (extent > 1.0)
        throw Error("the zoom region spans " + fmt(extent) +
                    " times the view: it is no close-up (make it smaller, or widen fov_deg)");
    // Equal normalised extents keep the image's aspect (cropStretch = 1); near an edge the window
    // slides inside the view rather than shrinking.
    const double x0 = std::clamp(cu - 0.5 * extent, 0.0, 1.0 - extent);
    const double y0 = std::clamp(cv - 0.5 * extent, 0.0, 1.0 - extent);
    return CropWindow{x0, y0, x0 + extent, y0 + extent};
}

std::vector<PointLight> lightRig(const LightRigSpec& rig, const Vec3& position, const Vec3& target,
                                 const Vec3& up, double vfovDeg, double aspect) {
    std::vector<PointLight> lights;
    const auto place = [&](const Vec3& p) {
        PointLight light;
        light.position = p;
        light.intensity = rig.irradiance * (p - target).length2();  // I/d² = irradiance
        lights.push_back(light);
    };
    if (rig.rig == "headlight") {
        place(position);
        return lights;
    }
    if (rig.rig != "paper") throw Error("unknown light rig '" + rig.rig + "' (headlight or paper)");
    const Basis b = basisOf(target - position, up);
    const double D = (target - position).length();
    const double behind = rig.behind * D;
    const double tV = std::tan(radians(vfovDeg) * 0.5);
    double hx = D * tV * aspect, hy = D * tV;  // the view's half extent at the target's depth
    if (rig.angleDeg > 0.0) {
        // The same diagonal, at angleDeg off the view axis seen from the target.
        const double rho = (D + behind) * std::tan(radians(rig.angleDeg));
        const double n = std::sqrt(hx * hx + hy * hy);
        hx *= rho / n;
        hy *= rho / n;
    }
    for (const double sr : {-1.0, 1.0})
        for (const double su : {-1.0, 1.0})
            place(position - b.forward * behind + b.right * (sr * hx) + b.up * (su * hy));
    return lights;
}

Vec3 rotateAbout(const Vec3& p, const Vec3& centre, const Vec3& axis, double degrees) {
    // Rodrigues' rotation formula: v cos θ + (k × v) sin θ + k (k · v)(1 − cos θ).
    const double t = radians(degrees);
    const Vec3 v = p - centre;
    return centre + v * std::cos(t) + axis.cross(v) * std::sin(t) +
           axis * (axis.dot(v) * (1.0 - std::cos(t)));
}

std::vector<SceneSpec> orbitFrames(const SceneSpec& spec, int n) {
    if (n <= 0) return {spec};
    std::vector<SceneSpec> frames;
    const std::string stem = std::filesystem::path(spec.path).stem().string();
    for (int k = 0; k < n; ++k) {
        SceneSpec frame = spec;
        frame.orbitDeg = 360.0 * k / n;
        char suffix[32];
        std::snprintf(suffix, sizeof suffix, "-orbit-%03d", k);
        frame.outputSuffix = spec.outputSuffix + suffix;
        frame.title = spec.title + " " + fmt(frame.orbitDeg) + " deg";  // ASCII: captions
        frame.group = stem + "-orbit";
        frames.push_back(std::move(frame));
    }
    return frames;
}

bool hasComputedView(const SceneSpec& spec) {
    return spec.fit.enabled || spec.zoom.kind != ZoomSpec::Kind::None ||
           !spec.lightRig.rig.empty() || spec.orbitDeg != 0.0;
}

void resolveView(SceneSpec& spec, const std::vector<WorldBox>& objectBoxes) {
    if (!hasComputedView(spec)) return;
    const double aspect = double(spec.width) / spec.height;
    // The objects framed and orbited: the fit's named ones, or all.
    WorldBox box;
    for (size_t i = 0; i < spec.objects.size() && i < objectBoxes.size(); ++i)
        if (spec.fit.objects.empty() || std::find(spec.fit.objects.begin(), spec.fit.objects.end(),
                                                  spec.objects[i].name) != spec.fit.objects.end())
            box.grow(objectBoxes[i]);
    const std::string where = spec.path + ": camera.";
    if (spec.fit.enabled) {
        try {
            ViewDirection dir =
                viewDirection(spec.fit.view, spec.fit.azimuthDeg, spec.fit.elevationDeg);
            if (spec.fit.upGiven) dir.up = spec.cameraUp;
            const FittedCamera cam =
                fitCamera(box, dir, spec.fovDegrees, aspect, spec.fit.margin, spec.fit.method);
            spec.cameraPosition = cam.position;
            spec.cameraTarget = cam.target;
            spec.cameraUp = cam.up;
        } catch (const Error& e) {
            throw Error(where + "fit: " + e.what());
        }
    }
    if (spec.orbitDeg != 0.0) {
        // A turntable: the objects stay, the camera and its lights go round them.
        const Vec3 centre = box.empty() ? spec.cameraTarget : box.center();
        if (!(spec.cameraUp.length() > 0.0)) throw Error(where + "up: the zero vector");
        const Vec3 axis = normalized(spec.cameraUp);
        spec.cameraPosition = rotateAbout(spec.cameraPosition, centre, axis, spec.orbitDeg);
        spec.cameraTarget = rotateAbout(spec.cameraTarget, centre, axis, spec.orbitDeg);
        for (PointLight& light : spec.lights)
            light.position = rotateAbout(light.position, centre, axis, spec.orbitDeg);
    }
    if (!spec.zoom.objects.empty()) {  // a close-up of named objects: their world box
        WorldBox zoomBox;
        for (size_t i = 0; i < spec.objects.size() && i < objectBoxes.size(); ++i)
            if (std::find(spec.zoom.objects.begin(), spec.zoom.objects.end(),
                          spec.objects[i].name) != spec.zoom.objects.end())
                zoomBox.grow(objectBoxes[i]);
        if (zoomBox.empty())
            throw Error(where + "zoom.objects: the objects have no voxels to zoom on");
        spec.zoom.lo = zoomBox.lo;
        spec.zoom.hi = zoomBox.hi;
    }
    if (spec.zoom.kind != ZoomSpec::Kind::None) {
        try {
            spec.crop = zoomCrop(spec.zoom, spec.cameraPosition, spec.cameraTarget, spec.cameraUp,
                                 spec.fovDegrees, aspect);
        } catch (const Error& e) {
            throw Error(where + "zoom: " + e.what());
        }
    }
    if (!spec.lightRig.rig.empty()) {
        try {
            spec.lights = lightRig(spec.lightRig, spec.cameraPosition, spec.cameraTarget,
                                   spec.cameraUp, spec.fovDegrees, aspect);
        } catch (const Error& e) {
            throw Error(spec.path + ": lights.rig: " + e.what());
        }
    }
}

std::string frozenViewJson(const SceneSpec& spec) {
    std::string s = "\"camera\": {\"position\": " + vec(spec.cameraPosition) +
                    ", \"target\": " + vec(spec.cameraTarget) + ", \"up\": " + vec(spec.cameraUp) +
                    ", \"fov_deg\": " + fmt(spec.fovDegrees);
    const CropWindow& c = spec.crop;
    if (c.x0 != 0.0 || c.y0 != 0.0 || c.x1 != 1.0 || c.y1 != 1.0)
        s += ", \"crop\": [" + fmt(c.x0) + ", " + fmt(c.y0) + ", " + fmt(c.x1) + ", " + fmt(c.y1) +
             "]";
    s += "},\n\"lights\": [";
    for (size_t i = 0; i < spec.lights.size(); ++i) {
        const Spectrum& I = spec.lights[i].intensity;
        const std::string intensity =
            I[0] == I[1] && I[1] == I[2]
                ? fmt(I[0])
                : "[" + fmt(I[0]) + ", " + fmt(I[1]) + ", " + fmt(I[2]) + "]";
        s += std::string(i ? ",\n  " : "\n  ") + "{\"position\": " + vec(spec.lights[i].position) +
             ", \"intensity\": " + intensity + "}";
    }
    s += spec.lights.empty() ? "]" : "\n]";
    return s;
}

}  // namespace lobe
