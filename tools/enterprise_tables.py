#!/usr/bin/env python3
"""Energy-compensation tables of the Enterprise PBR material, computed with numpy.

Writes glsl_lib/enterprise/tables.glsl (GLSL const arrays and their lookups). All tables are sampled
on grids that include both ends (node i of n at i / (n - 1)), looked up with linear interpolation.

GGX (anisotropic GGX with height-correlated Smith G2, Heitz 2014; alpha = r^2, r the roughness):
    GGX_E[r][mu]     32 x 32 vec2 (A, B): the single-scattering lobe's directional albedo split over the
                     Schlick weights (F90 = 1): E_ss(F0) = F0 A + B; GGX_E = A + B is the albedo at F = 1.
    GGX_EAVG[r]      32 vec2: the cosine-weighted averages 2 int A mu dmu, 2 int B mu dmu (E_avg = sum).
Dielectric base (Kelemen & Szirmay-Kalos 2001, Kulla & Conty 2017): the albedo of the whole specular
lobe, single scattering plus the Kulla-Conty multiple-scattering lobe, for Schlick F0 = f0, F90 = 1:
    E_base = f0 A + B + F_ms (1 - E),   F_ms = F_avg^2 E_avg / (1 - F_avg (1 - E_avg)),   F_avg = f0 + (1 - f0) / 21
    BASE_E[f0][r][mu]  16 x 16 x 16,   BASE_EAVG[f0][r]  16 x 16.
Sheen (Estevez & Kulla 2017 "Charlie" distribution with the visibility 1 / (4 (mu_l + mu_v - mu_l mu_v)) of
Neubelt & Pettineo 2013; alpha = max(r, 0.1)^2):
    SHEEN_E[r][mu]   32 x 32,   SHEEN_EAVG[r]  32.

GGX albedos are integrated by importance-sampling visible normals (Heitz 2018) on a stratified grid
(the estimator of the albedo is G2 / G1(v) per sample); the sheen albedo by a product Gauss-Legendre
quadrature over the incident hemisphere. usage: tools/enterprise_tables.py [--print]
"""
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "glsl_lib", "enterprise", "tables.glsl")
N_GGX = 32
N_BASE = 16
N_SHEEN = 32
STRATA = 64                 # STRATA^2 VNDF samples per GGX entry
ALPHA_MIN = 1.0e-4          # as glsl_lib/enterprise/specular.glsl
MU_MIN = 1.0e-3             # the mu = 0 nodes are evaluated here (the albedo is continuous there)
SHEEN_R_MIN = 0.1


def nodes(n):
    return np.linspace(0.0, 1.0, n)


def ggx_alpha(r):
    return np.maximum(np.asarray(r, dtype=float) ** 2, ALPHA_MIN)


def lambda_ggx(z, alpha):
    z2 = np.maximum(z * z, 1e-12)
    return 0.5 * (np.sqrt(1.0 + alpha * alpha * (1.0 - z2) / z2) - 1.0)


def sample_vndf(v, alpha, u1, u2):
    """Visible normals of isotropic GGX for the view v = (sin, 0, cos) (Heitz 2018), arrays of u."""
    vh = np.array([alpha * v[0], 0.0, v[2]])
    vh /= np.linalg.norm(vh)
    t1 = np.array([0.0, 1.0, 0.0]) if vh[0] > 0 else np.array([1.0, 0.0, 0.0])
    t2 = np.cross(vh, t1)
    rad, phi = np.sqrt(u1), 2.0 * np.pi * u2
    a, b = rad * np.cos(phi), rad * np.sin(phi)
    s = 0.5 * (1.0 + vh[2])
    b = (1.0 - s) * np.sqrt(np.maximum(0.0, 1.0 - a * a)) + s * b
    c = np.sqrt(np.maximum(0.0, 1.0 - a * a - b * b))
    nh = a[:, None] * t1 + b[:, None] * t2 + c[:, None] * vh
    h = np.stack([alpha * nh[:, 0], alpha * nh[:, 1], np.maximum(0.0, nh[:, 2])], -1)
    return h / np.linalg.norm(h, axis=-1, keepdims=True)


def ggx_albedo_split(mu, r, strata=STRATA):
    """(A, B) of the single-scattering GGX lobe at view cosine mu, roughness r."""
    mu = max(float(mu), MU_MIN)
    alpha = float(ggx_alpha(r))
    g = (np.arange(strata) + 0.5) / strata
    u1, u2 = [x.ravel() for x in np.meshgrid(g, g)]
    v = np.array([np.sqrt(1.0 - mu * mu), 0.0, mu])
    h = sample_vndf(v, alpha, u1, u2)
    vdoth = h @ v
    l = 2.0 * vdoth[:, None] * h - v
    ok = l[:, 2] > 0
    lv = lambda_ggx(mu, alpha)
    w = np.where(ok, (1.0 + lv) / (1.0 + lv + lambda_ggx(np.where(ok, l[:, 2], 1.0), alpha)), 0.0)
    s = (1.0 - np.clip(vdoth, 0.0, 1.0)) ** 5
    return float(np.mean(w * (1.0 - s))), float(np.mean(w * s))


def cosine_average(f, n=48):
    """2 int_0^1 f(mu) mu dmu by Gauss-Legendre (f vectorised over its first argument's nodes)."""
    x, w = np.polynomial.legendre.leggauss(n)
    mu = 0.5 * (x + 1.0)
    return float(np.sum(w * 0.5 * 2.0 * mu * np.array([f(m) for m in mu])))


def f_avg(f0):
    """Cosine-weighted average of Schlick's Fresnel with F90 = 1: f0 + (1 - f0) 2 int (1 - mu)^5 mu = f0 + (1 - f0)/21."""
    return f0 + (1.0 - f0) / 21.0


def f_ms(f0, e_avg):
    """Kulla & Conty 2017: colour of the multiple-scattering lobe, F_avg^2 E_avg / (1 - F_avg (1 - E_avg))."""
    fa = f_avg(f0)
    return fa * fa * e_avg / (1.0 - fa * (1.0 - e_avg))


def ggx_tables(n=N_GGX, strata=STRATA):
    rs, mus = nodes(n), nodes(n)
    e = np.array([[ggx_albedo_split(m, r, strata) for m in mus] for r in rs])          # [r][mu][2]
    e_avg = np.array([[cosine_average(lambda m, r=r, k=k: ggx_albedo_split(m, r, strata)[k], 24) for k in (0, 1)]
                      for r in rs])
    return e, e_avg


def base_tables(n=N_BASE, strata=STRATA):
    f0s, rs, mus = nodes(n), nodes(n), nodes(n)
    ab = np.array([[ggx_albedo_split(m, r, strata) for m in mus] for r in rs])         # [r][mu][2]
    ab_avg = np.array([[cosine_average(lambda m, r=r, k=k: ggx_albedo_split(m, r, strata)[k], 24) for k in (0, 1)]
                       for r in rs])                                                    # [r][2]
    e1 = ab.sum(-1)                                                                     # [r][mu]
    e1_avg = ab_avg.sum(-1)                                                             # [r]
    f0 = f0s[:, None, None]
    fms = f_ms(f0, e1_avg[None, :, None])
    base = f0 * ab[None, ..., 0] + ab[None, ..., 1] + fms * (1.0 - e1[None])           # [f0][r][mu]
    base_avg = (f0s[:, None] * ab_avg[None, :, 0] + ab_avg[None, :, 1]
                + f_ms(f0s[:, None], e1_avg[None]) * (1.0 - e1_avg[None]))              # [f0][r]
    return base, base_avg


def sheen_alpha(r):
    return max(float(r), SHEEN_R_MIN) ** 2


def sheen_brdf(mu_v, mu_l, cos_phi, alpha):
    """Charlie D (Estevez & Kulla 2017) times the Neubelt-Pettineo visibility, for unit v and l."""
    sv, sl = np.sqrt(np.maximum(1.0 - mu_v * mu_v, 0.0)), np.sqrt(np.maximum(1.0 - mu_l * mu_l, 0.0))
    hz = mu_v + mu_l
    hlen2 = sv * sv + sl * sl + 2.0 * sv * sl * cos_phi + hz * hz
    nh2 = hz * hz / np.maximum(hlen2, 1e-12)
    inv = 1.0 / alpha
    d = (2.0 + inv) * np.maximum(1.0 - nh2, 0.0) ** (0.5 * inv) / (2.0 * np.pi)
    vis = 1.0 / (4.0 * (mu_l + mu_v - mu_l * mu_v))
    return d * vis


def sheen_albedo(mu, r, n_theta=96, n_phi=96):
    mu = max(float(mu), MU_MIN)
    alpha = sheen_alpha(r)
    x, w = np.polynomial.legendre.leggauss(n_theta)
    mu_l, w_l = 0.5 * (x + 1.0), 0.5 * w
    y, wy = np.polynomial.legendre.leggauss(n_phi)
    phi, w_p = np.pi * 0.5 * (y + 1.0), np.pi * 0.5 * wy                     # symmetric in phi: [0, pi], doubled
    ml, ph = np.meshgrid(mu_l, phi, indexing="ij")
    f = sheen_brdf(mu, ml, np.cos(ph), alpha)
    return float(2.0 * np.sum(f * ml * w_l[:, None] * w_p[None, :]))


def sheen_tables(n=N_SHEEN):
    rs, mus = nodes(n), nodes(n)
    e = np.array([[sheen_albedo(m, r) for m in mus] for r in rs])
    e_avg = np.array([cosine_average(lambda m, r=r: sheen_albedo(m, r), 24) for r in rs])
    return e, e_avg


def _vec4_rows(values, per_row):
    """Flat values packed four to a vec4 (large const float arrays compile slowly on Mesa; vec4 ones do not)."""
    v = np.asarray(values, dtype=float).ravel()
    v = np.concatenate([v, np.zeros(-len(v) % 4)]).reshape(-1, 4)
    items = ["vec4(%.6f, %.6f, %.6f, %.6f)" % tuple(x) for x in v]
    return ",\n".join("    " + ", ".join(items[i:i + per_row]) for i in range(0, len(items), per_row))


LOOKUPS = """
// Element k of a table stored four to a vec4.
#define MG_EPBR_AT(table, k) (table[(k) >> 2][(k) & 3])

// Linear interpolation between grid nodes at i / (n - 1): lower node and weight of a coordinate in [0, 1].
void mg_epbr_cell(float x, int n, out int i, out float t)
{
    float p = clamp(x, 0.0, 1.0) * float(n - 1);
    i = min(int(floor(p)), n - 2);
    t = p - float(i);
}

vec2 mg_epbr_ggx_e_at(int k)
{
    vec4 v = MG_EPBR_GGX_E[k >> 1];
    return (k & 1) == 0 ? v.xy : v.zw;
}

// (A, B) of the GGX lobe at roughness r and view cosine mu: E_ss = F0 A + B (Schlick, F90 = 1).
vec2 mg_epbr_ggx_e(float r, float mu)
{
    int i, j;
    float s, t;
    mg_epbr_cell(r, 32, i, s);
    mg_epbr_cell(mu, 32, j, t);
    int k = i * 32 + j;
    return mix(mix(mg_epbr_ggx_e_at(k), mg_epbr_ggx_e_at(k + 1), t), mix(mg_epbr_ggx_e_at(k + 32), mg_epbr_ggx_e_at(k + 33), t), s);
}

vec2 mg_epbr_ggx_eavg(float r)
{
    int i;
    float s;
    mg_epbr_cell(r, 32, i, s);
    vec4 v = vec4(MG_EPBR_AT(MG_EPBR_GGX_EAVG, 2 * i), MG_EPBR_AT(MG_EPBR_GGX_EAVG, 2 * i + 1),
                  MG_EPBR_AT(MG_EPBR_GGX_EAVG, 2 * i + 2), MG_EPBR_AT(MG_EPBR_GGX_EAVG, 2 * i + 3));
    return mix(v.xy, v.zw, s);
}

// Albedo of the whole specular lobe (single + multiple scattering) for Schlick F0 = f0, F90 = 1.
float mg_epbr_base_e(float f0, float r, float mu)
{
    int i, j, l;
    float s, t, u;
    mg_epbr_cell(f0, 16, i, s);
    mg_epbr_cell(r, 16, j, t);
    mg_epbr_cell(mu, 16, l, u);
    int k = (i * 16 + j) * 16 + l;
    float a = mix(mix(MG_EPBR_AT(MG_EPBR_BASE_E, k), MG_EPBR_AT(MG_EPBR_BASE_E, k + 1), u), mix(MG_EPBR_AT(MG_EPBR_BASE_E, k + 16), MG_EPBR_AT(MG_EPBR_BASE_E, k + 17), u), t);
    k += 256;
    float b = mix(mix(MG_EPBR_AT(MG_EPBR_BASE_E, k), MG_EPBR_AT(MG_EPBR_BASE_E, k + 1), u), mix(MG_EPBR_AT(MG_EPBR_BASE_E, k + 16), MG_EPBR_AT(MG_EPBR_BASE_E, k + 17), u), t);
    return mix(a, b, s);
}

float mg_epbr_base_eavg(float f0, float r)
{
    int i, j;
    float s, t;
    mg_epbr_cell(f0, 16, i, s);
    mg_epbr_cell(r, 16, j, t);
    int k = i * 16 + j;
    return mix(mix(MG_EPBR_AT(MG_EPBR_BASE_EAVG, k), MG_EPBR_AT(MG_EPBR_BASE_EAVG, k + 1), t), mix(MG_EPBR_AT(MG_EPBR_BASE_EAVG, k + 16), MG_EPBR_AT(MG_EPBR_BASE_EAVG, k + 17), t), s);
}

// Per channel, for a coloured F0.
vec3 mg_epbr_base_e3(vec3 f0, float r, float mu)
{
    return vec3(mg_epbr_base_e(f0.r, r, mu), mg_epbr_base_e(f0.g, r, mu), mg_epbr_base_e(f0.b, r, mu));
}

vec3 mg_epbr_base_eavg3(vec3 f0, float r)
{
    return vec3(mg_epbr_base_eavg(f0.r, r), mg_epbr_base_eavg(f0.g, r), mg_epbr_base_eavg(f0.b, r));
}

float mg_epbr_sheen_e(float r, float mu)
{
    int i, j;
    float s, t;
    mg_epbr_cell(r, 32, i, s);
    mg_epbr_cell(mu, 32, j, t);
    int k = i * 32 + j;
    return mix(mix(MG_EPBR_AT(MG_EPBR_SHEEN_E, k), MG_EPBR_AT(MG_EPBR_SHEEN_E, k + 1), t), mix(MG_EPBR_AT(MG_EPBR_SHEEN_E, k + 32), MG_EPBR_AT(MG_EPBR_SHEEN_E, k + 33), t), s);
}

float mg_epbr_sheen_eavg(float r)
{
    int i;
    float s;
    mg_epbr_cell(r, 32, i, s);
    return mix(MG_EPBR_AT(MG_EPBR_SHEEN_EAVG, i), MG_EPBR_AT(MG_EPBR_SHEEN_EAVG, i + 1), s);
}
"""


def write(ggx, ggx_avg, base, base_avg, sheen, sheen_avg, path=OUT):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write("// Energy-compensation tables of the Enterprise PBR material (Dassault Systemes DSPBR 2025x,\n"
                "// \"Energy compensation\"; Kelemen & Szirmay-Kalos 2001; Kulla & Conty 2017), computed with numpy by\n"
                "// tools/enterprise_tables.py (see its docstring for the quantities). Nodes at i / (n - 1). Generated.\n\n")
        for name, values, comment in (
                ("MG_EPBR_GGX_E", ggx, "GGX (A, B) [roughness][mu], 32 x 32 (A, B interleaved)"),
                ("MG_EPBR_GGX_EAVG", ggx_avg, "GGX cosine-weighted averages (A_avg, B_avg) [roughness], 32"),
                ("MG_EPBR_BASE_E", base, "dielectric base: albedo of the compensated specular lobe [f0][roughness][mu], 16 x 16 x 16"),
                ("MG_EPBR_BASE_EAVG", base_avg, "its cosine-weighted average [f0][roughness], 16 x 16"),
                ("MG_EPBR_SHEEN_E", sheen, "sheen albedo [sheen roughness][mu], 32 x 32"),
                ("MG_EPBR_SHEEN_EAVG", sheen_avg, "its cosine-weighted average [sheen roughness], 32")):
            n = (np.asarray(values).size + 3) // 4
            f.write("// %s\nconst vec4 %s[%d] = vec4[%d](\n%s);\n\n" % (comment, name, n, n, _vec4_rows(values, 4)))
        f.write(LOOKUPS)


def main(argv):
    ggx, ggx_avg = ggx_tables()
    base, base_avg = base_tables()
    sheen, sheen_avg = sheen_tables()
    write(ggx, ggx_avg, base, base_avg, sheen, sheen_avg)
    print("wrote %s: GGX E %s, base E %s, sheen E %s; E_avg(r=0.5) = %.4f"
          % (os.path.relpath(OUT, ROOT), ggx.shape[:2], base.shape, sheen.shape, float(np.sum(ggx_avg[16]))))
    if "--print" in argv:
        print("GGX E (A+B) rows r = 0, 0.5, 1:", ggx.sum(-1)[[0, 15, 31]].round(3))
        print("sheen E_avg:", sheen_avg.round(3))


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
