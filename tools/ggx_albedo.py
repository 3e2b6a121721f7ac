#!/usr/bin/env python3
"""Directional albedo of the GGX microfacet reflection lobe, computed with numpy: a table and an analytic fit.

E(mu, alpha) = integral of f_ss(l, v) cos(theta_l) dl for isotropic GGX with height-correlated Smith G2,
split over the Schlick Fresnel weights: E = F0 * A(mu, alpha) + F90 * B(mu, alpha), with
A = int (1 - (1 - v.h)^5) f cos, B = int (1 - v.h)^5 f cos (f without Fresnel). Integrated by
importance-sampling visible normals (Heitz 2018) on a stratified grid: the estimator is F G2 / G1(v).

Writes glsl_lib/pbrlib/microfacet/albedo_fit.glsl, a least-squares polynomial fit of the table (the
table itself is checked against Monte Carlo in tests/nodes/test_pbr_microfacet.py; shaders carry only the fit).
usage: tools/ggx_albedo.py
"""
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "glsl_lib", "pbrlib", "microfacet")
N = 32                      # table size over mu and alpha
STRATA = 64                 # STRATA^2 samples per entry
DEG = 6                     # total degree of the fit


def lambda_ggx(z, alpha):
    z2 = np.maximum(z * z, 1e-12)
    return 0.5 * (np.sqrt(1.0 + alpha * alpha * (1.0 - z2) / z2) - 1.0)


def sample_vndf(v, alpha, u1, u2):
    """Heitz 2018: visible normal for view v = (sin, 0, cos), isotropic alpha; arrays of u."""
    vh = np.array([alpha * v[0], 0.0, v[2]])
    vh /= np.linalg.norm(vh)
    lensq = vh[0] ** 2 + vh[1] ** 2
    t1 = np.array([-vh[1], vh[0], 0.0]) / np.sqrt(lensq) if lensq > 0 else np.array([1.0, 0.0, 0.0])
    t2 = np.cross(vh, t1)
    r = np.sqrt(u1)
    phi = 2 * np.pi * u2
    a = r * np.cos(phi)
    b = r * np.sin(phi)
    s = 0.5 * (1.0 + vh[2])
    b = (1.0 - s) * np.sqrt(np.maximum(0.0, 1.0 - a * a)) + s * b
    c = np.sqrt(np.maximum(0.0, 1.0 - a * a - b * b))
    nh = a[:, None] * t1 + b[:, None] * t2 + c[:, None] * vh
    h = np.stack([alpha * nh[:, 0], alpha * nh[:, 1], np.maximum(0.0, nh[:, 2])], -1)
    return h / np.linalg.norm(h, axis=-1, keepdims=True)


def albedo(mu, alpha, strata=STRATA, jitter=None):
    """(A, B) for one view cosine and roughness."""
    g = (np.arange(strata) + 0.5) / strata
    u1, u2 = [x.ravel() for x in np.meshgrid(g, g)]
    if jitter is not None:
        u1 = np.clip(u1 + (jitter.random(u1.shape) - 0.5) / strata, 0, 1 - 1e-9)
        u2 = np.clip(u2 + (jitter.random(u2.shape) - 0.5) / strata, 0, 1 - 1e-9)
    v = np.array([np.sqrt(1 - mu * mu), 0.0, mu])
    h = sample_vndf(v, alpha, u1, u2)
    vdoth = h @ v
    l = 2 * vdoth[:, None] * h - v
    ok = l[:, 2] > 0
    w = np.where(ok, (1 + lambda_ggx(mu, alpha)) / (1 + lambda_ggx(mu, alpha) + lambda_ggx(np.where(ok, l[:, 2], 1.0), alpha)), 0.0)
    s = (1 - np.clip(vdoth, 0, 1)) ** 5
    return float(np.mean(w * (1 - s))), float(np.mean(w * s))


def grid():
    mus = (np.arange(N) + 0.5) / N
    alphas = (np.arange(N) + 0.5) / N
    return mus, alphas


def table():
    mus, alphas = grid()
    return np.array([[albedo(m, a) for m in mus] for a in alphas])   # [alpha][mu][A,B]


def design(mu, alpha):
    """Monomials of the fit of the difference from the mirror limit (alpha = 0: A = 1 - (1 - mu)^5,
    B = (1 - mu)^5): x = 1 - sqrt(mu), y = sqrt(alpha), x^i y^j with j >= 1, total degree <= DEG."""
    x, y = 1.0 - np.sqrt(mu), np.sqrt(alpha)
    cols, names = [], []
    for i in range(DEG + 1):
        for j in range(1, DEG + 1 - i):
            cols.append(x ** i * y ** j)
            names.append((i, j))
    return np.stack(cols, -1), names


def fit(tab):
    mus, alphas = grid()
    mm, aa = np.meshgrid(mus, alphas)
    X, names = design(mm.ravel(), aa.ravel())
    s = (1.0 - mm.ravel()) ** 5
    limit = [1.0 - s, s]
    coef = [np.linalg.lstsq(X, tab[..., k].ravel() - limit[k], rcond=None)[0] for k in range(2)]
    err = max(np.abs(X @ coef[k] + limit[k] - tab[..., k].ravel()).max() for k in range(2))
    return coef, names, err


def glsl_poly(coef, names):
    """Horner form in x of polynomials in y: sum_i x^i (sum_j c_ij y^j)."""
    c = dict(zip(names, coef))
    def in_y(i):
        js = sorted(j for (ii, j) in names if ii == i)
        e = "%.7g" % c[(i, js[-1])]
        for j in reversed(js[:-1]):
            e = "(%s) * y + %.7g" % (e, c[(i, j)])
        return "(%s) * y" % e
    e = in_y(DEG - 1)
    for i in reversed(range(DEG - 1)):
        e = "(%s) * x\n        + %s" % (e, in_y(i))
    return e.replace("+ -", "- ")


def write(tab, coef, names, err):
    with open(os.path.join(OUT, "albedo_fit.glsl"), "w") as f:
        f.write("// Directional albedo of GGX reflection with height-correlated Smith G2 (Heitz 2014), split over\n"
                "// Schlick weights: the mirror limit plus a least-squares polynomial in x = 1 - sqrt(mu), y = sqrt(alpha)\n"
                "// (total degree 6, every term with y) fitted to the table "
                "of tools/ggx_albedo.py; max error %.4f. Generated.\n" % err)
        f.write("vec2 mg_ggx_albedo_fit(float mu, float alpha)\n{\n"
                "    float x = 1.0 - sqrt(clamp(mu, 0.0, 1.0)), y = sqrt(clamp(alpha, 0.0, 1.0));\n"
                )
        f.write("    float s = pow(1.0 - clamp(mu, 0.0, 1.0), 5.0);\n")
        f.write("    float A = 1.0 - s + %s;\n" % glsl_poly(coef[0], names))
        f.write("    float B = s + %s;\n" % glsl_poly(coef[1], names))
        f.write("    return clamp(vec2(A, B), 0.0, 1.0);\n}\n")


def main():
    tab = table()
    coef, names, err = fit(tab)
    write(tab, coef, names, err)
    print("table %dx%d integrated; fit written, max error %.4f" % (N, N, err))


if __name__ == "__main__":
    sys.exit(main())
