#!/usr/bin/env python3
"""Directional albedo of the qualitative Oren-Nayar model, integrated numerically, and a fit for GLSL.

E(mu, r) = A(r) + B(r) G(mu), with G(mu) = 1/pi * integral over the hemisphere of (s/t) cos(theta_l),
s = L.V - (N.L)(N.V), t = max(N.L, N.V) where s > 0. G depends on the view angle only; this prints
G on a grid and the coefficients of a polynomial fit used by glsl_lib/pbrlib/bsdf/oren_nayar.glsl.
"""
import numpy as np


def G(mu, n=800):
    sv = np.sqrt(max(0.0, 1.0 - mu * mu))
    V = np.array([sv, 0.0, mu])
    th = (np.arange(n) + 0.5) / n * (np.pi / 2)
    ph = (np.arange(2 * n) + 0.5) / (2 * n) * (2 * np.pi)
    T, P = np.meshgrid(th, ph, indexing="ij")
    L = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], -1)
    nl = L[..., 2]
    s = L @ V - nl * mu
    st = np.where(s > 0, s / np.maximum(nl, mu), 0.0)
    dw = np.sin(T) * (np.pi / 2 / n) * (2 * np.pi / (2 * n))
    return float((st * nl * dw).sum() / np.pi)


def main():
    mus = np.linspace(0.0, 1.0, 41)
    g = np.array([G(m) for m in mus])
    coeffs = np.polyfit(mus, g, 5)
    fit = np.polyval(coeffs, mus)
    print("G(mu):", np.round(g, 5).tolist())
    print("fit (highest power first):", [float("%.6g" % c) for c in coeffs])
    print("max abs error: %.2e" % np.abs(fit - g).max())


if __name__ == "__main__":
    main()
