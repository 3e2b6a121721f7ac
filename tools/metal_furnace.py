#!/usr/bin/env python3
"""Developer tool: rough metals in a white furnace, ours against MaterialX's, ring by ring over the whole sphere
(docs/differences/README.md, rough metals at roughness 1).

A uniform white environment of radiance 1, no lights: a lobe whose Fresnel is 1 at every angle (a
generalized_schlick_bsdf with color0 = color90 = 1, or a conductor of that reflectance) absorbs nothing, so
with multiple scattering accounted for it returns exactly 1 at every pixel; anything below 1 is energy lost,
above 1 energy gained. For each roughness it prints the mean over the sphere and over rings of the sphere's
projected radius (the centre is seen head-on, the outer ring at grazing angles), ours and MaterialX's.
Then, in the scoreboard's scene (its sky), the same lobe and a standard_surface metal at specular_roughness 1:
the difference ours - MaterialX per ring, in 8-bit sRGB steps, and the scoreboard's verdict.

usage: tools/metal_furnace.py [--size 128] [--image PATH]
--image writes, at roughness 1: ours | MaterialX's (furnace, red where below 0.98) | |ours - MaterialX| x8 in
the scoreboard's scene.
"""
import argparse
import os
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

import numpy as np  # noqa: E402

from mtlxgen import compare, images, pipeline  # noqa: E402
from mtlxgen.reference import MaterialXReference  # noqa: E402
from mtlxgen.render import Renderer  # noqa: E402

HEAD = '<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n'
MATERIAL = ('<surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" '
            'nodename="s" /></surfacematerial>\n</materialx>\n')
SCHLICK = (HEAD + '<generalized_schlick_bsdf name="b" type="BSDF"><input name="roughness" type="vector2" '
           'value="%(a)g, %(a)g" /><input name="color0" type="color3" value="1, 1, 1" />'
           '<input name="color90" type="color3" value="1, 1, 1" /></generalized_schlick_bsdf>'
           '<surface name="s" type="surfaceshader"><input name="bsdf" type="BSDF" nodename="b" /></surface>' + MATERIAL)
METAL = (HEAD + '<standard_surface name="s" type="surfaceshader"><input name="metalness" type="float" value="1" />'
         '<input name="base_color" type="color3" value="%(c)s" /><input name="specular_roughness" type="float" '
         'value="%(r)g" /></standard_surface>' + MATERIAL)
GOLD = (HEAD + '<generalized_schlick_bsdf name="b" type="BSDF"><input name="roughness" type="vector2" '
        'value="%(a)g, %(a)g" /><input name="color0" type="color3" value="%(c)s" />'
        '<input name="color90" type="color3" value="1, 1, 1" /></generalized_schlick_bsdf>'
        '<surface name="s" type="surfaceshader"><input name="bsdf" type="BSDF" nodename="b" /></surface>' + MATERIAL)
# N.V per pixel, drawn by the same renderer: the model's albedo is looked up by it
NDOTV = (HEAD + '<normal name="n" type="vector3"><input name="space" type="string" value="world" /></normal>'
         '<viewdirection name="v" type="vector3" /><dotproduct name="d" type="float">'
         '<input name="in1" type="vector3" nodename="n" /><input name="in2" type="vector3" nodename="v" /></dotproduct>'
         '<multiply name="neg" type="float"><input name="in1" type="float" nodename="d" />'
         '<input name="in2" type="float" value="-1" /></multiply>'
         '<convert name="c" type="color3"><input name="in" type="float" nodename="neg" /></convert>'
         '<surface_unlit name="s" type="surfaceshader"><input name="emission_color" type="color3" nodename="c" />'
         '</surface_unlit>' + MATERIAL)
ALPHAS = (0.25, 0.5, 0.75, 1.0)


def _lambda(mu, a):
    t2 = (1.0 - mu * mu) / np.maximum(mu * mu, 1e-12)
    return 0.5 * (-1.0 + np.sqrt(1.0 + a * a * t2))


def conductor_fresnel(c, n, k):
    """Unpolarized Fresnel reflectance of a conductor of complex IOR n + ik at incidence cosine c (the standard
    exact form, e.g. Born & Wolf; per channel)."""
    c2, s2 = c * c, 1.0 - c * c
    a2b2 = np.sqrt((n * n - k * k - s2) ** 2 + 4.0 * n * n * k * k)
    a = np.sqrt(np.maximum(0.5 * (a2b2 + n * n - k * k - s2), 0.0))
    rs = (a2b2 + c2 - 2.0 * a * c) / (a2b2 + c2 + 2.0 * a * c)
    rp = rs * (c2 * a2b2 + s2 * s2 - 2.0 * a * c * s2) / (c2 * a2b2 + s2 * s2 + 2.0 * a * c * s2)
    return 0.5 * (rs + rp)


def artistic_ior(r, g):
    """Gulbrandsen 2014, 'Artist Friendly Metallic Fresnel': (n, k) from reflectivity r and edge colour g."""
    r = np.clip(np.asarray(r, dtype=float), 0.0, 0.99)
    g = np.asarray(g, dtype=float)
    n = g * (1.0 - r) / (1.0 + r) + (1.0 - g) * (1.0 + np.sqrt(r)) / (1.0 - np.sqrt(r))
    k = np.sqrt(np.maximum(r * (n + 1.0) ** 2 - (n - 1.0) ** 2, 0.0) / (1.0 - r))
    return n, k


def model_albedo(mu, a, f0, n=200, fresnel=None):
    """What the lobe should reflect in a white furnace, by numerical integration (not by any shader): the
    single-scattering albedo of GGX (Walter et al. 2007) with Smith's height-correlated masking-shadowing
    (Heitz 2014) and Schlick's Fresnel f0 + (1 - f0)(1 - v.h)^5, times the multiple-scattering compensation
    1 + f0 (1 - E) / E that both renderers use (Turquin 2019; E the albedo with F = 1). Per channel."""
    th = (np.arange(n) + 0.5) / n * (np.pi / 2)
    ph = (np.arange(2 * n) + 0.5) / (2 * n) * 2 * np.pi
    t, p = np.meshgrid(th, ph, indexing="ij")
    l = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1)
    v = np.array([np.sqrt(1.0 - mu * mu), 0.0, mu])
    h = l + v
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    nh, vh, nl = h[..., 2], np.clip((h * v).sum(-1), 0.0, 1.0), l[..., 2]
    d = a * a / (np.pi * (nh * nh * (a * a - 1.0) + 1.0) ** 2)
    g = 1.0 / (1.0 + _lambda(mu, a) + _lambda(nl, a))
    w = d * g / (4.0 * mu) * np.sin(t) * (np.pi / 2 / n) * (np.pi / n)
    e = w.sum()
    f0 = np.asarray(f0, dtype=float)
    if fresnel is not None:         # fresnel(cos) -> per-channel reflectance; f0 = fresnel(1)
        fv = fresnel(vh[..., None])
        ef = np.array([(w * fv[..., k]).sum() for k in range(fv.shape[-1])])
        f0 = fresnel(np.ones(1))[0]
        return ef * (1.0 + f0 * (1.0 - e) / e)
    ef = np.array([(w * (c + (1.0 - c) * (1.0 - vh) ** 5)).sum() for c in f0])
    return ef * (1.0 + f0 * (1.0 - e) / e)
RINGS = (0.0, 0.5, 0.7, 0.8, 0.9, 0.95, 1.0)


def rings(covered):
    """Boolean masks of the sphere's pixels by projected radius / sphere radius, RINGS' bounds."""
    size = covered.shape[0]
    ys, xs = np.nonzero(covered)
    cy, cx = ys.mean(), xs.mean()
    radius = np.sqrt(covered.sum() / np.pi)
    y, x = np.mgrid[0:size, 0:size]
    rel = np.hypot(x - cx, y - cy) / radius
    return [covered & (rel >= lo) & (rel < hi) for lo, hi in zip(RINGS[:-1], RINGS[1:])]


def draw(renderer, ref, folder, text, name):
    path = os.path.join(folder, name + ".mtlx")
    with open(path, "w") as f:
        f.write(text)
    shader = pipeline.generate(path, ["m"])[0]
    ours = renderer.render(shader)
    vs, fs, tex, _ = ref.generate(path, "m")
    theirs, _ = renderer.render_timed(vs, fs, {}, tex)
    return ours, theirs


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--size", type=int, default=128)
    ap.add_argument("--image", default=None)
    args = ap.parse_args()
    ref = MaterialXReference(color_management=True)
    white = np.ones((64, 128, 3), np.float32)
    labels = ["%g-%g" % (lo, hi) for lo, hi in zip(RINGS[:-1], RINGS[1:])]
    print("White furnace, generalized_schlick_bsdf F = 1: mean reflected (1 = all that arrives), ours / MaterialX's")
    print("| alpha | sphere | " + " | ".join("ring " + s for s in labels) + " | MaterialX pixels < 0.98 |")
    print("|---" * (len(labels) + 3) + "|")
    furnace_one = None
    with tempfile.TemporaryDirectory() as tmp:
        with Renderer(size=args.size, environment=white) as r:
            for a in ALPHAS:
                ours, theirs = draw(r, ref, tmp, SCHLICK % {"a": a}, "furnace_%g" % a)
                covered = theirs[..., 3] > 0.99
                o, t = ours[..., 0], theirs[..., 0]
                cells = ["%.3f / %.3f" % (o[m].mean(), t[m].mean()) for m in rings(covered)]
                print("| %g | %.3f / %.3f | %s | %.0f%% |" % (a, o[covered].mean(), t[covered].mean(), " | ".join(cells),
                                                             100.0 * (t[covered] < 0.98).mean()))
                if a == 1.0:
                    furnace_one = (o, t, covered)
            gold = (0.944, 0.776, 0.373)
            mu_img = draw(r, ref, tmp, NDOTV, "ndotv")[0][..., 0]
            mus = np.linspace(0.02, 1.0, 50)
            print()
            print("White furnace, generalized_schlick_bsdf color0 = gold %s, color90 = 1: mean over R, G, B, "
                  "ours / MaterialX's / the model (numerical integral)" % (gold,))
            print("| alpha | sphere | " + " | ".join("ring " + s for s in labels) + " |")
            print("|---" * (len(labels) + 2) + "|")
            for a in (0.5, 1.0):
                table = np.array([model_albedo(m, a, gold) for m in mus])
                ours, theirs = draw(r, ref, tmp, GOLD % {"a": a, "c": "%g, %g, %g" % gold}, "gold_%g" % a)
                covered = theirs[..., 3] > 0.99
                mu = np.clip(mu_img, 0.02, 1.0)
                model = np.stack([np.interp(mu, mus, table[:, k]) for k in range(3)], -1)
                o, t = ours[..., :3].mean(-1), theirs[..., :3].mean(-1)
                mm = model.mean(-1)
                cells = ["%.3f / %.3f / %.3f" % (o[m].mean(), t[m].mean(), mm[m].mean()) for m in rings(covered)]
                print("| %g | %.3f / %.3f / %.3f | %s |" % (a, o[covered].mean(), t[covered].mean(), mm[covered].mean(),
                                                           " | ".join(cells)))
            nk = artistic_ior(gold, (1.0, 1.0, 1.0))
            print()
            print("White furnace, standard_surface metalness 1, base_color gold, specular_color 1 (a conductor of the "
                  "artistic IOR, Gulbrandsen 2014): ours / MaterialX's / the model")
            print("| specular_roughness | sphere | " + " | ".join("ring " + s for s in labels) + " |")
            print("|---" * (len(labels) + 2) + "|")
            for rough in (0.7, 1.0):
                a = rough * rough
                table = np.array([model_albedo(m, a, gold, fresnel=lambda c: conductor_fresnel(c, nk[0], nk[1]))
                                  for m in mus])
                ours, theirs = draw(r, ref, tmp, METAL % {"c": "%g, %g, %g" % gold, "r": rough}, "metal_%g" % rough)
                covered = theirs[..., 3] > 0.99
                model = np.stack([np.interp(np.clip(mu_img, 0.02, 1.0), mus, table[:, k]) for k in range(3)], -1)
                o, t, mm = ours[..., :3].mean(-1), theirs[..., :3].mean(-1), model.mean(-1)
                cells = ["%.3f / %.3f / %.3f" % (o[m].mean(), t[m].mean(), mm[m].mean()) for m in rings(covered)]
                print("| %g | %.3f / %.3f / %.3f | %s |" % (rough, o[covered].mean(), t[covered].mean(),
                                                           mm[covered].mean(), " | ".join(cells)))
        print()
        print("Scoreboard scene: ours - MaterialX's per ring, mean signed difference in 8-bit sRGB steps; verdict")
        print("| material | " + " | ".join("ring " + s for s in labels) + " | parity |")
        print("|---" * (len(labels) + 2) + "|")
        cases = [("schlick F=1 alpha %g" % a, SCHLICK % {"a": a}) for a in ALPHAS] + [
            ("standard_surface metal %s r %g" % (c, rough), METAL % {"c": c, "r": rough})
            for c in ("1, 1, 1", "0.944, 0.776, 0.373") for rough in (0.5, 0.8, 1.0)]
        scene_one = None
        with Renderer.scoreboard(size=args.size) as r:
            for name, text in cases:
                ours, theirs = draw(r, ref, tmp, text, "scene_%d" % len(name))
                covered = theirs[..., 3] > 0.99
                a8 = images.to_srgb8(ours)[..., :3].astype(np.int16)
                b8 = images.to_srgb8(theirs)[..., :3].astype(np.int16)
                signed = (a8 - b8).mean(-1)
                cells = ["%+.1f" % signed[m].mean() for m in rings(covered)]
                print("| %s | %s | %s |" % (name, " | ".join(cells), compare.parity(ours, theirs)))
                if name == "schlick F=1 alpha 1":
                    scene_one = (a8, b8)
    if args.image and furnace_one and scene_one:
        o, t, covered = furnace_one
        grey = lambda v: np.repeat(np.clip(v, 0, 1)[..., None], 3, -1)    # noqa: E731
        a, b = grey(o), grey(t)
        low = covered & (t < 0.98)
        b[low] = np.stack([np.ones(low.sum()), t[low] ** 8, t[low] ** 8], -1)
        srgb = [images.to_srgb8(np.concatenate([p, np.ones(p.shape[:2] + (1,))], -1).astype(np.float32))[..., :3]
                for p in (a, b)]
        d = np.abs(scene_one[0] - scene_one[1]).max(-1)
        heat = np.repeat(np.clip(d * 8, 0, 255)[..., None], 3, -1).astype(np.uint8)
        images.write_image(args.image, np.concatenate(srgb + [heat], axis=1))
        print("image: %s" % args.image, file=sys.stderr)


if __name__ == "__main__":
    main()
