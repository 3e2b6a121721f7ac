"""MaterialX's TestSuite/pbrlib at parity with MaterialX, every element, drawn by the scoreboard's own
harness; the elements that differ on purpose (or are still open) are listed in docs/differences/README.md
with their reason and a side-by-side image, and that list is checked here too."""
import glob
import os

import numpy as np
import pytest

from conftest import DATA_TESTSUITE, TESTSUITE, corpus_params
from util import assert_harness_parity, scoreboard_elements

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PBRLIB = os.path.join(TESTSUITE, "pbrlib")
DIFFERENCES_DOC = os.path.join(ROOT, "docs", "differences")

# (document, element) -> the image under docs/differences/<document>/ that shows the difference
DIFFERENCES = {
    ("displaced_material", "surfacematerial1"): "surfacematerial1.png",
    ("displaced_material", "surfacematerial2"): "surfacematerial2.png",
    ("flake_surfaceshader", "flake_surfaceshader"): "flake_surfaceshader.png",
    ("lama_sheen", "LamaSheenTest"): "LamaSheenTest.png",
    ("mapped_surfaceshader", "UnitMappedShaderMaterial"): "UnitMappedShaderMaterial.png",
}


def _elements():
    params = []
    for path, element in scoreboard_elements(sorted(glob.glob(os.path.join(PBRLIB, "**", "*.mtlx"), recursive=True))):
        name = os.path.splitext(os.path.basename(path))[0]
        if (name, element) not in DIFFERENCES:      # (lama_surface.mtlx defines nodes only: no elements)
            params.append(pytest.param(path, element, id="%s:%s" % (name, element)))
    return params


@pytest.mark.corpus
@pytest.mark.parametrize("path, element", corpus_params(_elements, width=2))
def test_pbrlib_element_at_parity(harness, reference, path, element):
    try:
        theirs = reference.generate(path, element)
    except LookupError as e:    # MaterialX has no GLSL for it (volumematerial): not counted by the scoreboard
        pytest.skip("MaterialX does not generate it: %s" % e)
    assert_harness_parity(harness, reference, path, element, theirs)


def test_every_listed_difference_is_documented_with_an_image():
    with open(os.path.join(DIFFERENCES_DOC, "README.md")) as f:
        readme = f.read()
    for (doc, element), image in sorted(DIFFERENCES.items()):
        assert os.path.isfile(os.path.join(DIFFERENCES_DOC, doc, image)), (doc, image)
        assert "`%s/" % doc in readme and element.split("/")[0] in readme, (doc, element)


# transp_hint: OpenPBR transmission 0.8 at the default roughness 0.3, at parity (with the rest, above). MaterialX's
# rough environment transmission gains energy towards the silhouette (in a uniform environment brighter than the
# environment itself); ours is held to what the interface does not reflect (tests/nodes/test_rough_transmission.py),
# which at this roughness touches too few pixels to break parity. Smooth, the two agree.

def _transp_hint(tmp_path, roughness):
    src = os.path.join(DATA_TESTSUITE, "pbrlib", "surfaceshader", "transparency_hints.mtlx")
    text = open(src).read().replace(
        '<input name="transmission_weight" type="float" value="0.8" />',
        '<input name="transmission_weight" type="float" value="0.8" />'
        '<input name="specular_roughness" type="float" value="%g" />' % roughness)
    path = os.path.join(str(tmp_path), "transparency_hints_r%g.mtlx" % roughness)
    open(path, "w").write(text)
    return path


def test_transp_hint_at_parity_when_smooth(harness, reference, tmp_path):
    assert_harness_parity(harness, reference, _transp_hint(tmp_path, 0.0), "transp_hint")


def test_rough_transmission_never_exceeds_the_furnace_where_materialx_does(reference, tmp_path):
    """A uniform white environment: what a dielectric transmits can never exceed it. Ours stays under 1 at
    every pixel; MaterialX's outer ring averages well over 1 (the reason transp_hint differs)."""
    from test_furnace import white_environment
    from mtlxgen.draw.renderer import Renderer
    from util import bsdf_material, render_with_materialx, write_doc
    body = bsdf_material('<dielectric_bsdf name="b" type="BSDF"><input name="roughness" type="vector2" value="0.3, 0.3" />'
                         '<input name="ior" type="float" value="1.5" /><input name="scatter_mode" type="string" value="T" />'
                         '</dielectric_bsdf>')
    path = write_doc(tmp_path, body)
    size = 96
    with Renderer(size=size, environment=white_environment()) as r:
        ours, theirs = render_with_materialx(r, reference, path, "m")

    def outer_ring(img):
        covered = img[..., 3] > 0.5
        radius = (covered.sum() / 3.14159265) ** 0.5
        y, x = [a - (size - 1) / 2 for a in np.mgrid[0:size, 0:size]]
        return covered & (np.hypot(x, y) > 0.95 * radius)

    assert ours[..., :3][ours[..., 3] > 0.5].max() <= 1.0 + 1e-3
    assert theirs[..., :3][outer_ring(theirs)].mean() > 1.1
