// The directional albedo of a specular lobe at normal incidence, a(0) = ∫ f(n, wo) cos θo dωo,
// by deterministic quadrature: what an object's `brdf.albedo` scales its lobe to (the magnitude
// as a controlled variable: docs/scene-format.md, docs/assign.md).
//
// Why normal incidence: it is where a viewer near the light sees the highlight's peak, it is one
// number per model with no choice of azimuth (at θi = 0 an anisotropic lobe's albedo does not
// depend on φi), and every lobe — mirror- or half-vector-centred, retro-reflective — is centred on
// the normal there, so polar coordinates about n resolve it. Per band; the scale uses the mean of
// the three bands (equal for every model whose parameters are band-flat).
//
// Quadrature: θo on [0, π/2] in 81 panels, [0, 1e-7] and then geometric from 1e-7 to π/2 (so lobes
// from 1e-6 rad wide to the whole hemisphere get several panels), 8-point Gauss–Legendre per panel
// (Abramowitz & Stegun, Table 25.4); φo by the trapezoid rule on 64 points (spectrally accurate
// for a smooth periodic integrand). analysis/properties.h's Monte Carlo estimator is the
// independent check (tests/materials/test_albedo.cpp).
#pragma once

#include "materials/brdf.h"

namespace lobe {

Spectrum normalIncidenceAlbedoBands(const Brdf& brdf);
double normalIncidenceAlbedo(const Brdf& brdf);  // mean over the bands

// The factor that scales `brdf` to albedo `target` at normal incidence; throws lobe::Error when
// the lobe reflects nothing there (no factor can reach the target).
double albedoScale(const Brdf& brdf, double target);

}  // namespace lobe
