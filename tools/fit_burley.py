#!/usr/bin/env python3
"""Directional albedo of Burley's diffuse model, integrated numerically, and its fit for GLSL.

f = rho/pi (1 + (F90 - 1)(1 - mu_l)^5)(1 + (F90 - 1)(1 - mu_v)^5), F90 = 0.5 + 2 r (L.H)^2
(Burley 2012, "Physically-Based Shading at Disney"). f is quadratic in r, so the albedo is exactly
E(mu, r) = e0(mu) + r e1(mu) + r^2 e2(mu); each e_i is fitted by a polynomial in x = 1 - mu.
This prints the coefficients used by glsl_lib/pbrlib/bsdf/burley.glsl.
"""
import numpy as np


def albedo(mu, r, n=300):
    th = (np.arange(n) + 0.5) / n * (np.pi / 2)
    ph = (np.arange(2 * n) + 0.5) / (2 * n) * (2 * np.pi)
    T, P = np.meshgrid(th, ph, indexing="ij")
    L = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], -1)
    V = np.array([np.sqrt(max(0.0, 1.0 - mu * mu)), 0.0, mu])
    H = L + V
    H /= np.linalg.norm(H, axis=-1, keepdims=True)
    nl = L[..., 2]
    f90 = 0.5 + 2.0 * r * (L * H).sum(-1) ** 2
    f = (1 + (f90 - 1) * (1 - nl) ** 5) * (1 + (f90 - 1) * (1 - mu) ** 5) / np.pi
    dw = np.sin(T) * (np.pi / 2 / n) * (2 * np.pi / (2 * n))
    return float((f * nl * dw).sum())


def main():
    mus = np.linspace(0.02, 1.0, 50)
    E = np.array([[albedo(m, r) for m in mus] for r in (0.0, 0.5, 1.0)])
    e2 = 2 * (E[2] - 2 * E[1] + E[0])
    e1 = E[2] - E[0] - e2
    x = 1 - mus
    for name, e in (("e0", E[0]), ("e1", e1), ("e2", e2)):
        c = np.polyfit(x, e, 6)
        print(name, "(highest power first):", ", ".join("%.6g" % v for v in c),
              " max abs error %.1e" % np.abs(np.polyval(c, x) - e).max())


if __name__ == "__main__":
    main()
