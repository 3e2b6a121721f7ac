#!/usr/bin/env python3
"""Developer tool: rough refraction in a white furnace, ours against MaterialX's (docs/differences/README.md,
rough transmission).

A uniform white environment of radiance 1, no lights: a dielectric_bsdf in scatter_mode RT (one interface,
reflection and transmission) can return at most 1 at any pixel. For each roughness (alpha) it prints, over
the sphere: ours (mean, max), ours with the refraction's energy cap lifted (MG_REFRACTION_UNBOUNDED:
MaterialX's estimate, shown at parity with MaterialX by tests/nodes/test_rough_transmission.py), MaterialX's
(mean, max, outer ring mean), the share of the sphere where the cap lowers the estimate by over 2%, and
how much of that share MaterialX draws above 1.

usage: tools/refraction_furnace.py [--ior 1.5] [--size 128] [--image PATH --image-alpha 0.5]
--image writes ours | MaterialX's (red where above 1) | where the cap binds (white), at --image-alpha.
"""
import argparse
import os
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

import numpy as np  # noqa: E402

from mtlxgen.base import images
from mtlxgen import pipeline  # noqa: E402
from mtlxgen.apps.reference import MaterialXReference  # noqa: E402
from mtlxgen.draw.renderer import Renderer  # noqa: E402

DOC = """<?xml version="1.0"?>
<materialx version="1.39">
  <dielectric_bsdf name="b" type="BSDF"><input name="ior" type="float" value="%g" />
    <input name="roughness" type="vector2" value="%g, %g" /><input name="scatter_mode" type="string" value="RT" />
  </dielectric_bsdf>
  <surface name="s" type="surfaceshader"><input name="bsdf" type="BSDF" nodename="b" /></surface>
  <surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="s" /></surfacematerial>
</materialx>
"""
ALPHAS = (0.1, 0.25, 0.5, 0.75, 1.0)


def unbounded(fragment):
    head, rest = fragment.split("\n", 1)
    return head + "\n#define MG_REFRACTION_UNBOUNDED\n" + rest


def measure(renderer, ref, folder, alpha, ior):
    path = os.path.join(folder, "furnace_%g_%g.mtlx" % (alpha, ior))
    with open(path, "w") as f:
        f.write(DOC % (ior, alpha, alpha))
    shader = pipeline.generate(path, elements=["m"])[0]
    ours = renderer.render(shader)
    lifted, _ = renderer.render_timed(shader.vertex, unbounded(shader.fragment), {}, {})
    vs, fs, tex, _ = ref.generate(path, "m")
    theirs, _ = renderer.render_timed(vs, fs, {}, tex)
    return ours, lifted, theirs


def outer_ring(covered):
    size = covered.shape[0]
    radius = np.sqrt(covered.sum() / np.pi)
    y, x = np.mgrid[0:size, 0:size] - (size - 1) / 2.0
    return covered & (np.hypot(x, y) > 0.9 * radius)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ior", type=float, default=1.5)
    ap.add_argument("--size", type=int, default=128)
    ap.add_argument("--image", default=None)
    ap.add_argument("--image-alpha", type=float, default=0.5)
    args = ap.parse_args()
    ref = MaterialXReference()
    white = np.ones((64, 128, 3), np.float32)
    print("| alpha | ours mean | ours max | MaterialX mean | MaterialX max | MaterialX outer ring | capped (> 2%) "
          "| MaterialX > 1 where capped | MaterialX max elsewhere |")
    print("|---|---|---|---|---|---|---|---|---|")
    with Renderer(size=args.size, environment=white) as r, tempfile.TemporaryDirectory() as tmp:
        for alpha in sorted(set(ALPHAS) | ({args.image_alpha} if args.image else set())):
            ours, lifted, theirs = measure(r, ref, tmp, alpha, args.ior)
            covered = ours[..., 3] > 0.99
            o, u, t = ours[..., 0], lifted[..., 0], theirs[..., 0]
            capped = covered & (o < u * 0.98)
            print("| %g | %.4f | %.4f | %.4f | %.4f | %.4f | %.1f%% | %s | %.4f |" % (
                alpha, o[covered].mean(), o[covered].max(), t[covered].mean(), t[covered].max(),
                t[outer_ring(covered)].mean(), 100.0 * capped.sum() / covered.sum(),
                "%.1f%%" % (100.0 * (t[capped] > 1.0).mean()) if capped.any() else "-",
                t[covered & ~capped].max()))
            if args.image and alpha == args.image_alpha:
                grey = lambda v: np.repeat(np.clip(v, 0, 1)[..., None], 3, -1)    # noqa: E731
                a = grey(o)
                b = grey(t)
                over = covered & (t > 1.0)
                b[over] = np.stack([np.ones(over.sum()), 1.0 / t[over] ** 4, 1.0 / t[over] ** 4], -1)
                c = grey(capped.astype(np.float32))
                panels = [np.concatenate([p, np.ones(p.shape[:2] + (1,))], -1) for p in (a, b, c)]
                srgb = [images.to_srgb8(p.astype(np.float32))[..., :3] for p in panels]
                images.write_image(args.image, np.concatenate(srgb, axis=1))
                print("image: %s (alpha %g, ior %g)" % (args.image, alpha, args.ior), file=sys.stderr)


if __name__ == "__main__":
    main()
