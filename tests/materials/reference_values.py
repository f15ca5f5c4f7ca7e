#!/usr/bin/env python3
"""Reference values for tests/materials/test_brdf_values.cpp, computed independently of the C++
code: every formula below is typed again from docs/models.md (the normative
definitions), using only the Python standard library (math, cmath). The C++ test compares its
models with the printed values to 1e-9 relative.

Run:  python3 tests/materials/reference_values.py
It prints one C++ initializer line per case: {model, {settings}, wi, wo, {f_700, f_546.1, f_435.8}}.
Directions are given as exact decimal literals (17 significant digits) so that both sides start
from the same doubles; the script normalises nothing (it builds unit vectors from angles).

It also prints the analytic directional albedos used in test_properties.cpp.
"""
import cmath
import math

PI = math.pi


def direction(theta_deg, phi_deg):
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return (math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t))


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def norm(a):
    return math.sqrt(dot(a, a))


def cos_alpha(wi, wo):
    # r(wi) = 2(n.wi)n - wi = (-x, -y, z); cos alpha = max(0, r.wo)
    r = (-wi[0], -wi[1], wi[2])
    return max(0.0, dot(r, wo))


def half(wi, wo):
    h = add(wi, wo)
    n = norm(h)
    return (h[0] / n, h[1] / n, h[2] / n)


def fresnel_exact(eta, kappa, c):
    # docs/models.md: F = 1/2 |g-c|^2/|g+c|^2 (1 + |c(g+c)-1|^2/|c(g-c)+1|^2), g^2 = n^2 + c^2 - 1
    n = complex(eta, kappa)
    g = cmath.sqrt(n * n + c * c - 1)
    if g.real < 0:
        g = -g
    a = abs(g - c) ** 2 / abs(g + c) ** 2
    b = abs(c * (g + c) - 1) ** 2 / abs(c * (g - c) + 1) ** 2
    return 0.5 * a * (1 + b)


def fresnel_schlick(f0, c):
    return f0 + (1 - f0) * (1 - c) ** 5


def phong(p, wi, wo):
    return p['ks'] * cos_alpha(wi, wo) ** p['exponent']


def strauss(p, wi, wo):
    kf, kg, kj = 1.12, 1.01, 0.1

    def F(x):
        return (1 / (x - kf) ** 2 - 1 / kf ** 2) / (1 / (1 - kf) ** 2 - 1 / kf ** 2)

    def G(x):
        return (1 / (1 - kg) ** 2 - 1 / (x - kg) ** 2) / (1 / (1 - kg) ** 2 - 1 / kg ** 2)

    xi = math.acos(wi[2]) / (PI / 2)
    xo = math.acos(wo[2]) / (PI / 2)
    s, m, t = p['smoothness'], p['metalness'], p['transparency']
    rd = (1 - s ** 3) * (1 - t)
    rn = (1 - t) - rd
    h = 3 / (1 - s)
    j = F(xi) * G(xi) * G(xo)
    rj = min(1.0, rn + (rn + kj) * j)
    cs = 1 + m * (1 - F(xi)) * (p['color'] - 1)
    return p['ks'] * cs * rj * cos_alpha(wi, wo) ** h


def schlick_lewis(p, wi, wo):
    u, n = cos_alpha(wi, wo), p['exponent']
    return p['ks'] * (n + 2) / (2 * PI) * u / (n - n * u + u)


def ward(p, wi, wo):
    H = add(wi, wo)
    ax, ay = p['alpha_x'], p['alpha_y']
    e = -((H[0] / ax) ** 2 + (H[1] / ay) ** 2) / H[2] ** 2
    return p['rho_s'] * math.exp(e) / (4 * PI * ax * ay * math.sqrt(wi[2] * wo[2]))


def cook_torrance(p, wi, wo):
    h = half(wi, wo)
    m = p['m']
    th = math.acos(h[2])
    D = math.exp(-math.tan(th) ** 2 / m ** 2) / (PI * m ** 2 * math.cos(th) ** 4)
    G = min(1.0, 2 * h[2] * wo[2] / dot(wo, h), 2 * h[2] * wi[2] / dot(wo, h))
    F = fresnel_exact(p['eta'], p['kappa'], dot(wi, h))
    return p['ks'] * F * D * G / (4 * wi[2] * wo[2])


def lafortune(p, wi, wo):
    b = p['cx'] * wi[0] * wo[0] + p['cy'] * wi[1] * wo[1] + p['cz'] * wi[2] * wo[2]
    return p['rho_s'] * max(0.0, b) ** p['exponent']


def ashikhmin_shirley(p, wi, wo):
    h = half(wi, wo)
    nu, nv = p['nu'], p['nv']
    s2 = h[0] ** 2 + h[1] ** 2
    e = (nu * h[0] ** 2 + nv * h[1] ** 2) / s2 if s2 > 0 else 1.0
    F = fresnel_schlick(p['rs'], dot(h, wi))
    return (math.sqrt((nu + 1) * (nv + 1)) / (8 * PI) * h[2] ** e
            / (dot(h, wi) * max(wi[2], wo[2])) * F)


def lambert(p, wi, wo):
    return p['kd'] / PI


MODELS = {
    'phong': (phong, {'ks': 0.8, 'exponent': 10.0}),
    'strauss': (strauss, {'ks': 0.5, 'smoothness': 0.75, 'metalness': 0.5, 'transparency': 0.0,
                          'color': 1.0}),
    'schlick_lewis': (schlick_lewis, {'ks': 0.8, 'exponent': 10.0}),
    'ward': (ward, {'rho_s': 0.05, 'alpha_x': 0.05, 'alpha_y': 0.3}),
    'cook_torrance': (cook_torrance, {'ks': 0.8, 'm': 0.08, 'eta': 1.6, 'kappa': 0.2}),
    'lafortune': (lafortune, {'rho_s': 1.0, 'cx': -1.0, 'cy': -1.0, 'cz': 0.95, 'exponent': 20.0}),
    'ashikhmin_shirley': (ashikhmin_shirley, {'rs': 0.05, 'nu': 10.0, 'nv': 1000.0}),
    'lambert': (lambert, {'kd': 0.2}),
}

# (model, overrides: {name: value or (v700, v546, v435)}, wi angles (θ, φ) deg, wo angles)
CASES = [
    ('phong', {}, (30, 10), (35, 185)),
    ('phong', {}, (60, -40), (50, 150)),
    ('phong', {'ks': 0.5, 'exponent': (2.0, 7.5, 150.0)}, (10, 0), (12, 175)),
    ('strauss', {}, (30, 10), (35, 185)),
    ('strauss', {}, (75, 100), (70, 275)),
    ('strauss', {'smoothness': 0.3, 'metalness': 1.0, 'color': (0.9, 0.5, 0.2)}, (60, -40),
     (50, 150)),
    ('strauss', {'transparency': 0.4}, (5, 0), (8, 170)),
    ('schlick_lewis', {}, (30, 10), (35, 185)),
    ('schlick_lewis', {}, (60, -40), (50, 150)),
    ('schlick_lewis', {'exponent': (1.0, 40.0, 500.0)}, (10, 0), (12, 178)),
    ('ward', {}, (30, 10), (35, 185)),
    ('ward', {}, (60, -40), (50, 150)),
    ('ward', {'rho_s': 0.3, 'alpha_x': 0.2, 'alpha_y': 0.2}, (75, 100), (70, 275)),
    ('ward', {}, (45, 30), (45, 30)),
    ('cook_torrance', {}, (30, 10), (35, 185)),
    ('cook_torrance', {}, (60, -40), (58, 138)),
    ('cook_torrance', {'m': 0.3, 'eta': (0.16, 0.37, 1.59), 'kappa': (3.9, 2.8, 1.9)}, (75, 100),
     (70, 275)),
    ('cook_torrance', {'m': 0.5}, (85, 0), (20, 180)),
    ('lafortune', {}, (30, 10), (35, 185)),
    ('lafortune', {}, (60, -40), (50, 150)),
    ('lafortune', {'cx': -1.0, 'cy': -0.6, 'cz': 1.0, 'exponent': (3.0, 10.0, 50.0)}, (40, 60),
     (45, 250)),
    ('ashikhmin_shirley', {}, (30, 10), (35, 185)),
    ('ashikhmin_shirley', {}, (60, 0), (58, 180.5)),
    ('ashikhmin_shirley', {'rs': 0.9, 'nu': 100.0, 'nv': 100.0}, (75, 100), (70, 275)),
    ('ashikhmin_shirley', {}, (0, 0), (0, 0)),
    ('lambert', {}, (30, 10), (35, 185)),
    ('lambert', {'kd': (1.0, 0.5, 0.0)}, (89, 0), (1, 0)),
    ('lambert', {}, (45, 30), (45, 30)),
]


def fmt(x):
    return repr(float(x))


def band_params(defaults, overrides, band):
    p = dict(defaults)
    for k, v in overrides.items():
        p[k] = v[band] if isinstance(v, tuple) else v
    return p


def setting_text(k, v):
    if isinstance(v, tuple):
        return '"%s=%s"' % (k, ','.join(repr(float(x)) for x in v))
    return '"%s=%s"' % (k, repr(float(v)))


def main():
    print('// model, settings, wi, wo, f per band (700, 546.1, 435.8 nm)')
    for model, overrides, ai, ao in CASES:
        fn, defaults = MODELS[model]
        wi, wo = direction(*ai), direction(*ao)
        f = [fn(band_params(defaults, overrides, b), wi, wo) for b in range(3)]
        settings = ', '.join(setting_text(k, v) for k, v in overrides.items())
        print('{"%s", {%s}, {%s}, {%s}, {%s}},  // wi (%g°, %g°), wo (%g°, %g°)' % (
            model, settings, ', '.join(fmt(x) for x in wi), ', '.join(fmt(x) for x in wo),
            ', '.join(fmt(x) for x in f), ai[0], ai[1], ao[0], ao[1]))

    # Analytic directional albedos at normal incidence (wi = n, so the mirror direction is n and
    # cos α = cos θo):
    #  Phong: a(0) = ks ∫ cos^n θ cos θ dω = ks · 2π/(n + 2).
    #  Schlick–Lewis: a(0) = ks (n+2)/(2π) · 2π ∫_0^1 S(u) u du, S(u) = u/(n − (n−1)u);
    #   the integral by Simpson's rule on 2·10^6 intervals (the integrand is smooth).
    print()
    for n in (1.0, 10.0, 100.0):
        print('phong ks=0.8 exponent=%g: a(0) = %s' % (n, fmt(0.8 * 2 * PI / (n + 2))))
    for n in (1.0, 10.0, 100.0):
        N = 2000000
        h = 1.0 / N

        def g(u):
            return u * u / (n - (n - 1) * u)
        s = g(0.0) + g(1.0)
        for i in range(1, N):
            s += (4 if i % 2 else 2) * g(i * h)
        integral = s * h / 3
        print('schlick_lewis ks=0.8 exponent=%g: a(0) = %s' % (n, fmt(0.8 * (n + 2) * integral)))


if __name__ == '__main__':
    main()
