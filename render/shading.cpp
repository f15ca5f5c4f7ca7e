#include "render/shading.h"

#include "materials/he_torrance_table.h"
#include "render/shading_simd.h"

#include <algorithm>
#include <cmath>

namespace lobe {

namespace {

// fn(light index, wi, g) for the lights of one point as forEachLightInFrame (core/light.h, the
// one light loop) walks them, g = cos θi / d² times the shadow transmittance; lights a shadow
// leaves at 0 are dropped.
template <class Fn>
inline void forEachLitLight(const std::vector<PointLight>& lights, const Frame& frame,
                            const Vec3& position, const Vec3& toViewer, const double* shadow,
                            Fn&& fn) {
    forEachLightInFrame(lights, frame, position, toViewer,
                        [&](const PointLight& light, const Vec3& wi, const Vec3&, double g) {
                            const size_t i = size_t(&light - lights.data());
                            if (shadow) {
                                g *= shadow[i];
                                if (!(g > 0.0)) return;
                            }
                            fn(i, wi, g);
                        });
}

// The light loops of directLighting and shadeTerms for one model's view (materials/brdf.h,
// ModelAtView): one function per model, chosen once per point by visitAtView, with the model's
// eval inlined and the sums kept in registers. onEvaluation() is called once per BRDF evaluation
// (a no-op except for `lobe cost`'s counting).
//   directLighting: Σ (kd/π + f_s · scale) · I · g
template <class View, class OnEvaluation>
Spectrum directLightingLoop(View& specular, const Material& material, const Frame& frame,
                            const Vec3& position, const Vec3& toViewer,
                            const std::vector<PointLight>& lights, const double* shadow,
                            OnEvaluation& onEvaluation) {
    const Spectrum diffuse = material.kd * kInvPi;
    Spectrum radiance;
    forEachLitLight(lights, frame, position, toViewer, shadow,
                    [&](size_t light, const Vec3& wi, double g) {
                        onEvaluation();
                        Spectrum f = diffuse;
                        if (material.specularOn) f += specular.eval(wi) * material.specularScale;
                        radiance += f * lights[light].intensity * g;
                    });
    return radiance;
}

//   shadeTerms: Σ kd/π · I · g and Σ f_s · scale · I · g apart
template <class View, class OnEvaluation>
ShadingTerms shadeTermsLoop(View& specular, const Material& m, const Frame& frame,
                            const Vec3& position, const Vec3& toViewer,
                            const std::vector<PointLight>& lights, const double* shadow,
                            OnEvaluation& onEvaluation) {
    const Spectrum diffuse = m.kd * kInvPi;
    Spectrum lambert, spec;
    forEachLitLight(lights, frame, position, toViewer, shadow,
                    [&](size_t light, const Vec3& wi, double g) {
                        onEvaluation();
                        const Spectrum& intensity = lights[light].intensity;
                        lambert += diffuse * intensity * g;
                        if (m.specularOn)
                            spec += specular.eval(wi) * m.specularScale * intensity * g;
                    });
    return {lambert, spec};
}

// Phong with one whole exponent for all bands (the usual case, and T1's, T2's and T3's): the light
// loop as one SIMD kernel (render/shading_simd.h). Null for every other material (the loops
// above).
inline const Phong* sharedWholePhong(const Material& m) {
    const Phong* phong = std::get_if<Phong>(&m.specular);
    if (!phong) return nullptr;
    const Spectrum& e = phong->exponent;
    return e[0] == e[1] && e[1] == e[2] && isWholeExponent(e[0]) ? phong : nullptr;
}

template <class OnEvaluation>
void countEvaluations(OnEvaluation& onEvaluation, long long n) {
    for (long long i = 0; i < n; ++i) onEvaluation();
}

// The kernel's sums for `m` when it is such a Phong (returns false otherwise). `frame` is turned
// to the viewer already; frameFree: only frame.n is set (ShadingPoint::setNormal), and cos α is
// worked out without the tangents. Nothing is lit when the viewer is not above the surface
// (wo.z ≤ 0, as in forEachLightInFrame).
template <class OnEvaluation>
bool phongKernelSums(const Material& m, const Frame& frame, bool frameFree, const Vec3& position,
                     const Vec3& toViewer, const std::vector<PointLight>& lights,
                     const double* shadow, bool combined, OnEvaluation& onEvaluation,
                     PhongSums& sums) {
    const Phong* phong = sharedWholePhong(m);
    if (!phong) return false;
    PhongPointInput in;
    in.frame = frame;
    if (frameFree) {
        in.frameFree = true;
        in.toViewer = toViewer;
        in.wo.z = toViewer.dot(frame.n);  // frame.toLocal(toViewer).z
    } else {
        in.wo = frame.toLocal(toViewer);
    }
    if (!(in.wo.z > 0.0)) return true;
    in.position = position;
    in.exponent = static_cast<unsigned>(phong->exponent[0]);
    const Spectrum diffuse = m.kd * kInvPi;
    for (int b = 0; b < kBandCount; ++b) {
        in.ks[b] = phong->ks[b];
        in.diffuse[b] = diffuse[b];
    }
    in.specularScale = m.specularScale;
    in.specularOn = m.specularOn;
    in.shadow = shadow;
    phongLightSums(in, lights, combined, sums);
    countEvaluations(onEvaluation, sums.evaluations);
    return true;
}

// Ward or Ashikhmin–Shirley whose shape parameters (αx, αy; nu, nv) are the same in every band
// (the usual case, and rendering 1's): the light loop as a SIMD kernel (render/shading_simd.h,
// within its stated tolerance of the loops above). False for every other material.
inline bool sharedShapeAniso(const Material& m, AnisoPointInput& in) {
    if (const Ward* ward = std::get_if<Ward>(&m.specular)) {
        const Spectrum &ax = ward->alphaX, &ay = ward->alphaY;
        if (!(ax[0] == ax[1] && ax[1] == ax[2] && ay[0] == ay[1] && ay[1] == ay[2])) return false;
        in.model = AnisoPointInput::Model::ward;
        in.shapeX = ax[0];
        in.shapeY = ay[0];
        for (int b = 0; b < kBandCount; ++b) in.reflectance[b] = ward->rhoS[b];
        return true;
    }
    if (const AshikhminShirley* as = std::get_if<AshikhminShirley>(&m.specular)) {
        const Spectrum &nu = as->nu, &nv = as->nv;
        if (!(nu[0] == nu[1] && nu[1] == nu[2] && nv[0] == nv[1] && nv[1] == nv[2])) return false;
        in.model = AnisoPointInput::Model::ashikhminShirley;
        in.shapeX = nu[0];
        in.shapeY = nv[0];
        const Spectrum norm = as->norms();
        for (int b = 0; b < kBandCount; ++b) {
            in.reflectance[b] = as->rs[b];
            in.norm[b] = norm[b];
        }
        return true;
    }
    return false;
}

// The kernel's sums for `m` when it is such a Ward or Ashikhmin–Shirley and the kernel takes the
// point (returns false otherwise: the caller runs the model's loop). `frame` is the full frame,
// turned to the viewer already. Nothing is lit when the viewer is not above the surface.
template <class OnEvaluation>
bool anisoKernelSums(const Material& m, const Frame& frame, const Vec3& position,
                     const Vec3& toViewer, const std::vector<PointLight>& lights,
                     const double* shadow, bool combined, OnEvaluation& onEvaluation,
                     PhongSums& sums) {
    AnisoPointInput in;
    if (!sharedShapeAniso(m, in)) return false;
    in.frame = frame;
    in.wo = frame.toLocal(toViewer);
    if (!(in.wo.z > 0.0)) return true;
    in.position = position;
    const Spectrum diffuse = m.kd * kInvPi;
    for (int b = 0; b < kBandCount; ++b) in.diffuse[b] = diffuse[b];
    in.specularScale = m.specularScale;
    in.specularOn = m.specularOn;
    in.shadow = shadow;
    if (!anisoLightSums(in, lights, combined, sums)) {
        sums = PhongSums();
        return false;
    }
    countEvaluations(onEvaluation, sums.evaluations);
    return true;
}

// He–Torrance read from its table (materials/he_torrance_table.h: previews and full renders;
// null without one, `--exact-brdf`): the lights' f in lanes, kLanes lights at a time
// (HeTorranceTable::evalLanes: the coordinates with SIMD, within 1e-12 of eval's f relative to
// the table's peak; docs/performance.md, round 7), then the sums of directLightingLoop
// (`combined`: into terms.lambert) or shadeTermsLoop in the lights' order, operation for
// operation. `frame` is turned to the viewer already.
inline const HeTorranceTable* heTorranceTableOf(const Material& m) {
    const HeTorrance* model = std::get_if<HeTorrance>(&m.specular);
    return model ? model->table.get() : nullptr;
}

template <class OnEvaluation>
ShadingTerms heTorranceTableLoop(const HeTorranceTable& table, const Material& m,
                                 const Frame& frame, const Vec3& position, const Vec3& toViewer,
                                 const std::vector<PointLight>& lights, const double* shadow,
                                 bool combined, OnEvaluation& onEvaluation) {
    constexpr int L = HeTorranceTable::kLanes;
    const Vec3 wo = frame.toLocal(toViewer);
    const Spectrum diffuse = m.kd * kInvPi;
    ShadingTerms terms;
    double wx[L], wy[L], wz[L], gs[L];
    size_t index[L];
    int n = 0;
    const auto flush = [&]() {
        Spectrum f[L];
        if (m.specularOn) table.evalLanes(n, wx, wy, wz, wo, f);
        for (int k = 0; k < n; ++k) {
            onEvaluation();
            const Spectrum& intensity = lights[index[k]].intensity;
            const double g = gs[k];
            if (combined) {
                Spectrum fk = diffuse;
                if (m.specularOn) fk += clampBrdfValue(f[k]) * m.specularScale;
                terms.lambert += fk * intensity * g;
            } else {
                terms.lambert += diffuse * intensity * g;
                if (m.specularOn)
                    terms.specular += clampBrdfValue(f[k]) * m.specularScale * intensity * g;
            }
        }
        n = 0;
    };
    forEachLitLight(lights, frame, position, toViewer, shadow,
                    [&](size_t light, const Vec3& wi, double g) {
                        wx[n] = wi.x;
                        wy[n] = wi.y;
                        wz[n] = wi.z;
                        gs[n] = g;
                        index[n] = light;
                        if (++n == L) flush();
                    });
    if (n > 0) flush();
    return terms;
}

// The normal of facingViewer (render/shading.h) alone.
inline Vec3 facingNormal(const Vec3& n, const Vec3& toViewer) {
    return n.dot(toViewer) < 0.0 ? -n : n;
}

template <class OnEvaluation>
Spectrum directLightingImpl(const Material& material, const Frame& frameIn, const Vec3& position,
                            const Vec3& toViewer, const std::vector<PointLight>& lights,
                            bool twoSided, OnEvaluation&& onEvaluation,
                            const double* shadow = nullptr) {
    const Frame frame = twoSided ? facingViewer(frameIn, toViewer) : frameIn;
    PhongSums sums;
    if (phongKernelSums(material, frame, false, position, toViewer, lights, shadow, true,
                        onEvaluation, sums) ||
        anisoKernelSums(material, frame, position, toViewer, lights, shadow, true, onEvaluation,
                        sums))
        return Spectrum(sums.lambert[0], sums.lambert[1], sums.lambert[2]);
    if (const HeTorranceTable* table = heTorranceTableOf(material))
        return heTorranceTableLoop(*table, material, frame, position, toViewer, lights, shadow,
                                   true, onEvaluation)
            .lambert;
    const Vec3 wo = frame.toLocal(toViewer);
    return visitAtView(material.specular, wo, [&](auto& specular) {
        return directLightingLoop(specular, material, frame, position, toViewer, lights, shadow,
                                  onEvaluation);
    });
}

template <class OnEvaluation>
ShadingTerms shadeTermsImpl(const ShadingPoint& point, const Vec3& toViewer,
                            const std::vector<PointLight>& lights, OnEvaluation&& onEvaluation);

template <class OnEvaluation>
Spectrum shadeImpl(const ShadingPoint& point, const Vec3& toViewer,
                   const std::vector<PointLight>& lights, OnEvaluation&& onEvaluation) {
    if (point.hasFrame) {
        if (point.highlight == point.colour) {
            const Material& m = *point.material;
            if (point.tangentsPending && sharedWholePhong(m)) {  // frame-free
                Frame frame;
                frame.n = facingNormal(point.frame.n, toViewer);
                PhongSums sums;
                phongKernelSums(m, frame, true, point.position, toViewer, lights, point.shadow,
                                true, onEvaluation, sums);
                return point.colour * Spectrum(sums.lambert[0], sums.lambert[1], sums.lambert[2]);
            }
            return point.colour * directLightingImpl(m, frameOf(point), point.position, toViewer,
                                                     lights, true, onEvaluation, point.shadow);
        }
        const ShadingTerms terms = shadeTermsImpl(point, toViewer, lights, onEvaluation);
        return terms.lambert + terms.specular;
    }
    Spectrum radiance;
    forEachLight(lights, point.position, [&](const PointLight& light, const Vec3&, double d2) {
        const double v = point.shadow ? point.shadow[&light - lights.data()] : 1.0;
        radiance += point.material->kd * kInvPi * light.intensity * (v / d2);
    });
    return point.colour * radiance;
}

template <class OnEvaluation>
ShadingTerms shadeTermsImpl(const ShadingPoint& point, const Vec3& toViewer,
                            const std::vector<PointLight>& lights, OnEvaluation&& onEvaluation) {
    const Material& m = *point.material;
    ShadingTerms terms;
    if (!point.hasFrame) {
        terms.lambert = shadeImpl(point, toViewer, lights, onEvaluation);
        return terms;
    }
    Frame frame;
    const bool frameFree = point.tangentsPending && sharedWholePhong(m);
    if (frameFree)
        frame.n = facingNormal(point.frame.n, toViewer);
    else
        frame = facingViewer(frameOf(point), toViewer);
    PhongSums sums;
    if (phongKernelSums(m, frame, frameFree, point.position, toViewer, lights, point.shadow, false,
                        onEvaluation, sums) ||
        anisoKernelSums(m, frame, point.position, toViewer, lights, point.shadow, false,
                        onEvaluation, sums)) {
        terms.lambert = Spectrum(sums.lambert[0], sums.lambert[1], sums.lambert[2]);
        terms.specular = Spectrum(sums.specular[0], sums.specular[1], sums.specular[2]);
    } else if (const HeTorranceTable* table = heTorranceTableOf(m)) {
        terms = heTorranceTableLoop(*table, m, frame, point.position, toViewer, lights,
                                    point.shadow, false, onEvaluation);
    } else {
        const Vec3 wo = frame.toLocal(toViewer);
        terms = visitAtView(m.specular, wo, [&](auto& specular) {
            return shadeTermsLoop(specular, m, frame, point.position, toViewer, lights,
                                  point.shadow, onEvaluation);
        });
    }
    terms.lambert = point.colour * terms.lambert;
    terms.specular = point.highlight * terms.specular;
    return terms;
}

struct NoCount {
    void operator()() const {}
};

}  // namespace

Spectrum directLighting(const Material& material, const Frame& frameIn, const Vec3& position,
                        const Vec3& toViewer, const std::vector<PointLight>& lights,
                        bool twoSided) {
    return directLightingImpl(material, frameIn, position, toViewer, lights, twoSided, NoCount{});
}

Spectrum shadeVolumeSample(const Material& material, const VolumeSample& sample,
                           const Vec3& toViewer, const std::vector<PointLight>& lights,
                           const Vec3& tangentAxis, const Vec3& fallbackAxis) {
    ShadingPoint point;
    point.material = &material;
    point.colour = point.highlight = sample.colour;
    point.position = sample.position;
    point.hasFrame = sample.hasNormal;
    if (sample.hasNormal)
        point.frame = Frame::fromNormalAndAxis(sample.normal, tangentAxis, fallbackAxis);
    return shade(point, toViewer, lights);
}

Spectrum shade(const ShadingPoint& point, const Vec3& toViewer,
               const std::vector<PointLight>& lights) {
    return shadeImpl(point, toViewer, lights, NoCount{});
}

Spectrum shade(const ShadingPoint& point, const Vec3& toViewer,
               const std::vector<PointLight>& lights, long long& brdfEvaluations) {
    return shadeImpl(point, toViewer, lights, [&] { ++brdfEvaluations; });
}

ShadingTerms shadeTerms(const ShadingPoint& point, const Vec3& toViewer,
                        const std::vector<PointLight>& lights) {
    return shadeTermsImpl(point, toViewer, lights, NoCount{});
}

void shadeSpecularPerModel(const ShadingPoint& point, const Vec3& toViewer,
                           const std::vector<PointLight>& lights, const std::vector<Brdf>& models,
                           Spectrum* out, const double* scales) {
    for (size_t m = 0; m < models.size(); ++m) out[m] = Spectrum(0.0);
    if (!point.hasFrame) return;
    const Frame frame = facingViewer(frameOf(point), toViewer);
    forEachLightInFrame(lights, frame, point.position, toViewer,
                        [&](const PointLight& light, const Vec3& wi, const Vec3& wo, double g) {
                            if (point.shadow) g *= point.shadow[&light - lights.data()];
                            const Spectrum irradiance = light.intensity * g;
                            for (size_t m = 0; m < models.size(); ++m)
                                out[m] += evalBrdf(models[m], wi, wo) *
                                          (scales ? irradiance * scales[m] : irradiance);
                        });
    for (size_t m = 0; m < models.size(); ++m) out[m] = point.highlight * out[m];
}

}  // namespace lobe
