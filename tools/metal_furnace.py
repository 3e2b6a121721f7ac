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

For a coloured conductor (standard_surface metalness 1, gold) the reference is a simulation, not a shader: a random
walk on GGX's microsurface (Heitz et al. 2016) gives the albedo with every order of scattering between microfacets,
each bounce weighted by the exact conductor Fresnel at its own angle (with F = 1 the walk returns 1.0000, and its
first order is the single-scattering integral). The renderers approximate the orders past the first by a factor on
the single-scattering lobe, 1 + F (1 - E) / E: ours with F at normal incidence (F0), MaterialX's with F at the view
angle, which rises towards 1 at grazing angles.

usage: tools/metal_furnace.py [--size 128] [--image PATH] [--gold-image PATH] [--walkers 40000]
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

from mtlxgen.draw import compare
from mtlxgen.base import images
from mtlxgen import pipeline  # noqa: E402
from mtlxgen.apps.reference import MaterialXReference  # noqa: E402
from mtlxgen.draw.renderer import Renderer  # noqa: E402

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


def model_albedo(mu, a, f0, n=200, fresnel=None, compensate=True):
    """What the lobe should reflect in a white furnace, by numerical integration (not by any shader): the
    single-scattering albedo of GGX (Walter et al. 2007) with Smith's height-correlated masking-shadowing
    (Heitz 2014) and Schlick's Fresnel f0 + (1 - f0)(1 - v.h)^5, times the multiple-scattering compensation
    1 + f0 (1 - E) / E that both renderers use (Turquin 2019; E the albedo with F = 1); compensate=False: the
    single-scattering albedo alone. Per channel."""
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
        f0 = fresnel(np.ones((1, 1)))[0]       # per channel (fresnel(np.ones(1))[0] would be the red one alone)
        return ef * (1.0 + f0 * (1.0 - e) / e) if compensate else ef
    ef = np.array([(w * (c + (1.0 - c) * (1.0 - vh) ** 5)).sum() for c in f0])
    return ef * (1.0 + f0 * (1.0 - e) / e) if compensate else ef
def _rw_lambda(wz, a):
    """Smith Lambda of GGX for unit directions of cosine wz (Heitz et al. 2016: negative below the horizon)."""
    wz = np.clip(wz, -1.0, 1.0)
    t2 = (1.0 - wz * wz) / np.maximum(wz * wz, 1e-12)
    s = np.sqrt(1.0 + a * a * t2)
    return np.where(wz > 0, 0.5 * (-1.0 + s), 0.5 * (-1.0 - s))

def _rw_visible_normal(w, a, rng):
    """Visible normals of isotropic GGX seen from direction w (pointing away from the surface, any hemisphere):
    in the stretched configuration (alpha 1) the normals are uniform over the upper hemisphere, so the visible ones
    follow max(0, w1.m): a cosine lobe about w1, kept where m is above the surface (rejection); then unstretched."""
    w1 = np.stack([a * w[:, 0], a * w[:, 1], w[:, 2]], -1)
    w1 /= np.linalg.norm(w1, axis=-1, keepdims=True)
    m = np.zeros_like(w1)
    todo = np.arange(len(w1))
    while len(todo):
        ww = w1[todo]
        u1, u2 = rng.random(len(todo)), rng.random(len(todo))
        r, phi = np.sqrt(u1), 2 * np.pi * u2
        local = np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(np.maximum(0.0, 1.0 - u1))], -1)
        # frame about ww
        up = np.where(np.abs(ww[:, 2:3]) < 0.999, np.array([[0, 0, 1.0]]), np.array([[1.0, 0, 0]]))
        t = np.cross(up, ww); t /= np.linalg.norm(t, axis=-1, keepdims=True)
        b = np.cross(ww, t)
        cand = local[:, 0:1] * t + local[:, 1:2] * b + local[:, 2:3] * ww
        ok = cand[:, 2] > 0
        m[todo[ok]] = cand[ok]
        todo = todo[~ok]
    m = np.stack([a * m[:, 0], a * m[:, 1], m[:, 2]], -1)
    return m / np.linalg.norm(m, axis=-1, keepdims=True)

def random_walk_albedo(mu, a, fresnel, n=200000, bounces=64, seed=1):
    """Directional albedo of a rough conductor with multiple scattering between its microfacets, simulated
    (Heitz, Hanika, d'Eon, Dachsbacher 2016, 'Multiple-Scattering Microfacet BSDFs with the Smith Model': a random
    walk on the microsurface of GGX with uniform heights). fresnel(cos) -> (..., 3). Returns (total, single)."""
    rng = np.random.default_rng(seed)
    wi = np.array([np.sqrt(1.0 - mu * mu), 0.0, mu])
    wr = np.tile(-wi, (n, 1))
    h = np.full(n, 1.0)                # C1(h) = (h + 1) / 2, heights uniform in [-1, 1]; start at the top
    energy = np.ones((n, 3))
    total = np.zeros(3)
    single = np.zeros(3)
    alive = np.arange(n)
    for order in range(bounces):
        w, hh = wr[alive], h[alive]
        U = rng.random(len(alive))
        c1 = np.clip(0.5 * (hh + 1.0), 0.0, 1.0)
        lam = _rw_lambda(w[:, 2], a)
        up = w[:, 2] > 0
        g1 = np.where(up, c1 ** np.where(up, lam, 1.0), 0.0)
        escape = up & (U > 1.0 - g1)
        if order > 0:
            total += energy[alive[escape]].sum(0)
            if order == 1:
                single += energy[alive[escape]].sum(0)
        stay = ~escape
        alive, w, hh, U, lam, c1 = alive[stay], w[stay], hh[stay], U[stay], lam[stay], c1[stay]
        if not len(alive):
            break
        newc1 = c1 / (1.0 - U) ** (1.0 / lam)
        h[alive] = np.clip(2.0 * newc1 - 1.0, -1.0, 1.0)
        wo = -w
        m = _rw_visible_normal(wo, a, rng)
        c = np.clip((wo * m).sum(-1), 0.0, 1.0)
        energy[alive] *= fresnel(c[:, None])
        wr[alive] = -wo + 2.0 * c[:, None] * m
    return total / n, single / n


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
    shader = pipeline.generate(path, elements=["m"])[0]
    ours = renderer.render(shader)
    vs, fs, tex, _ = ref.generate(path, "m")
    theirs, _ = renderer.render_timed(vs, fs, {}, tex)
    return ours, theirs


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--size", type=int, default=128)
    ap.add_argument("--image", default=None)
    ap.add_argument("--gold-image", default=None, help="the gold conductor at specular_roughness 1 in the furnace: "
                    "ours | MaterialX's against the random walk (red above it, blue below, full at 5%%, grey within "
                    "0.1%%), then |ours - MaterialX's| x8 in the scoreboard's scene")
    ap.add_argument("--walkers", type=int, default=40000, help="random walks per view angle")
    args = ap.parse_args()
    ref = MaterialXReference(color_management=True)
    white = np.ones((64, 128, 3), np.float32)
    labels = ["%g-%g" % (lo, hi) for lo, hi in zip(RINGS[:-1], RINGS[1:])]
    print("White furnace, generalized_schlick_bsdf F = 1: mean reflected (1 = all that arrives), ours / MaterialX's")
    print("| alpha | sphere | " + " | ".join("ring " + s for s in labels) + " | MaterialX pixels < 0.98 |")
    print("|---" * (len(labels) + 3) + "|")
    furnace_one = gold_one = scene_gold = None
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
                  "artistic IOR, Gulbrandsen 2014): ours / MaterialX's / the model (F0 compensation) / the random "
                  "walk (all orders of scattering, simulated)")
            print("| specular_roughness | sphere | " + " | ".join("ring " + s for s in labels) + " |")
            print("|---" * (len(labels) + 2) + "|")
            for rough in (0.7, 1.0):
                a = rough * rough
                fresnel = lambda c: conductor_fresnel(c, nk[0], nk[1])      # noqa: E731
                table = np.array([model_albedo(m, a, gold, fresnel=fresnel) for m in mus])
                walk_mus = np.linspace(0.02, 1.0, 25)
                walk = np.array([random_walk_albedo(m, a, fresnel, n=args.walkers)[0] for m in walk_mus])
                ours, theirs = draw(r, ref, tmp, METAL % {"c": "%g, %g, %g" % gold, "r": rough}, "metal_%g" % rough)
                covered = theirs[..., 3] > 0.99
                mu = np.clip(mu_img, 0.02, 1.0)
                model = np.stack([np.interp(mu, mus, table[:, k]) for k in range(3)], -1)
                truth = np.stack([np.interp(mu, walk_mus, walk[:, k]) for k in range(3)], -1)
                o, t, mm, w = ours[..., :3].mean(-1), theirs[..., :3].mean(-1), model.mean(-1), truth.mean(-1)
                cells = ["%.3f / %.3f / %.3f / %.3f" % (o[m].mean(), t[m].mean(), mm[m].mean(), w[m].mean())
                         for m in rings(covered)]
                print("| %g | %.3f / %.3f / %.3f / %.3f | %s |" % (rough, o[covered].mean(), t[covered].mean(),
                                                                  mm[covered].mean(), w[covered].mean(),
                                                                  " | ".join(cells)))
                rel_o, rel_t = o[covered] / w[covered] - 1.0, t[covered] / w[covered] - 1.0
                print("|   | ours against the walk: %+.1f%% to %+.1f%%; MaterialX's: %+.1f%% to %+.1f%% (5th to 95th "
                      "percentile over the sphere's pixels) |" % tuple(100 * np.percentile(x, p) for x in (rel_o, rel_t)
                                                                       for p in (5, 95)))
                if rough == 1.0:
                    gold_one = (o, t, w, covered)
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
                if name == "standard_surface metal 0.944, 0.776, 0.373 r 1":
                    scene_gold = (a8, b8)
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
    if args.gold_image and gold_one and scene_gold:
        o, t, w, covered = gold_one
        tiles = []
        for v in (o, t):                # against the walk: red above it, blue below, full at 5%
            dev = np.clip(np.where(covered, v / np.maximum(w, 1e-6) - 1.0, 0.0) / 0.05, -1.0, 1.0)
            rgb = np.stack([np.clip(dev, 0, 1), np.zeros_like(dev), np.clip(-dev, 0, 1)], -1)
            rgb[covered & (np.abs(dev) < 0.02)] = 0.25
            tiles.append((rgb * 255).astype(np.uint8))
        d = np.abs(scene_gold[0] - scene_gold[1]).max(-1)
        tiles.append(np.repeat(np.clip(d * 8, 0, 255)[..., None], 3, -1).astype(np.uint8))
        images.write_image(args.gold_image, np.concatenate(tiles, axis=1))
        print("image: %s" % args.gold_image, file=sys.stderr)


if __name__ == "__main__":
    main()
