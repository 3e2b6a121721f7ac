"""White-furnace figures of the Stride material (docs/materials.md, "Stride material"): every visibility x NDF over
gloss {0, 0.25, 0.5, 0.75, 1}, for white metal (metalness 1) and a white dielectric in the specular
workflow (specular 0.04, energy conservation), under a uniform white environment; prints a Markdown
table of the lowest and highest mean sphere radiance per visibility term.

    python tools/stride_furnace.py          (about a minute on llvmpipe)
"""
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from mtlxgen import pipeline                  # noqa: E402
from mtlxgen.draw.renderer import Renderer           # noqa: E402

VISIBILITY = ["implicit", "neumann", "cook_torrance", "kelemen", "smith_beckmann", "smith_ggx_correlated",
              "schlick_beckmann", "schlick_ggx"]
NDF = ["ggx", "beckmann", "blinn_phong"]
GLOSS = [0.0, 0.25, 0.5, 0.75, 1.0]
CONFIGS = {
    "metal": '<input name="diffuse" type="color3" value="1, 1, 1" /><input name="metalness" type="float" value="1" />',
    "dielectric": '<input name="diffuse" type="color3" value="1, 1, 1" /><input name="workflow" type="string" '
                  'value="specular" /><input name="specular" type="color3" value="0.04, 0.04, 0.04" />',
}


def furnace_means(renderer, folder, config, vis, ndf):
    means = []
    for gloss in GLOSS:
        path = os.path.join(folder, "furnace.mtlx")
        with open(path, "w") as f:
            f.write('<?xml version="1.0"?>\n<materialx version="1.39">\n<stride_material name="s" type="surfaceshader">'
                    '%s<input name="glossiness" type="float" value="%s" /><input name="visibility" type="string" '
                    'value="%s" /><input name="ndf" type="string" value="%s" /></stride_material>\n</materialx>\n'
                    % (CONFIGS[config], gloss, vis, ndf))
        img = renderer.render(pipeline.generate(path)[0])
        means.append(float(img[..., :3][img[..., 3] > 0].mean()))
    return means


def main():
    white = np.ones((32, 64, 3), np.float32)
    rows = {}
    with tempfile.TemporaryDirectory() as folder, Renderer(size=64, environment=white) as r:
        for vis in VISIBILITY:
            for config in CONFIGS:
                m = [x for ndf in NDF for x in furnace_means(r, folder, config, vis, ndf)]
                rows.setdefault(vis, []).extend([min(m), max(m)])
    print("| visibility | metal min | metal max | dielectric min | dielectric max |")
    print("|---|---|---|---|---|")
    for vis, v in rows.items():
        print("| %s | %s |" % (vis, " | ".join("%.3f" % x for x in v)))


if __name__ == "__main__":
    main()
