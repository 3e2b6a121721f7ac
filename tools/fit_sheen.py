#!/usr/bin/env python3
"""Directional albedo of the Conty-Kulla sheen BRDF, tabulated numerically for GLSL.

f = D / (4 (mu_l + mu_v - mu_l mu_v)), D = (2 + 1/r) sin(theta_h)^(1/r) / (2 pi)
(Conty & Kulla 2017, "Production Friendly Microfacet Sheen BRDF", with the smooth visibility of
Neubelt & Pettineo 2013). Prints a 32 x 32 table E[s][mu] used by glsl_lib/pbrlib/bsdf/sheen.glsl
(bilinear lookup): mu = i / 31, and rows evenly spaced in s = sqrt(r) from sqrt(R0) to 1 (r = s^2, R0 =
0.005 the GLSL's smallest roughness), because the albedo changes fastest at low roughness (a table
linear in r, interpolating towards r = 0, was 30% low at r = 0.04).
"""
import numpy as np

N = 32
R0 = 0.005


def albedo(mu, r, n=600):
    mu = max(mu, 1.0e-3)
    inv = 1.0 / max(r, 0.005)
    th = (np.arange(n) + 0.5) / n * (np.pi / 2)
    ph = (np.arange(2 * n) + 0.5) / (2 * n) * np.pi          # symmetric in phi: half the circle, twice
    T, P = np.meshgrid(th, ph, indexing="ij")
    L = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], -1)
    V = np.array([np.sqrt(1.0 - mu * mu), 0.0, mu])
    H = L + V
    H /= np.linalg.norm(H, axis=-1, keepdims=True)
    nl = L[..., 2]
    sin2 = np.clip(1.0 - H[..., 2] ** 2, 0.0, None)
    D = (2.0 + inv) * sin2 ** (0.5 * inv) / (2.0 * np.pi)
    f = D / (4.0 * (nl + mu - nl * mu))
    dw = np.sin(T) * (np.pi / 2 / n) * (np.pi / (2 * n))
    return float(2.0 * (f * nl * dw).sum())


def main():
    grid = [i / (N - 1) for i in range(N)]
    s0 = R0 ** 0.5
    rows = [(s0 + (1.0 - s0) * i / (N - 1)) ** 2 for i in range(N)]
    table = [[albedo(mu, r) for mu in grid] for r in rows]
    print(",\n".join("    " + ", ".join("%.4f" % v for v in row) for row in table))


if __name__ == "__main__":
    main()
