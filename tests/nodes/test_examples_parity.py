"""MaterialX's Examples (and the minimal documents that isolate what they needed) at parity with MaterialX,
drawn by the scoreboard's own harness: zero-weight lobes stay empty and an unconnected input with a default
geomprop reads the geometry whatever value is authored (gltf_pbr), USD documents without USD
provenance keep MaterialX's graph (UsdPreviewSurface glass), thin-film iridescence per polarization on
dielectrics and conductors (OpenPBR Pearl, Soap_Bubble), and transmission at IOR 1 under a film."""
import os

import numpy as np
import pytest

from conftest import DATA_EXAMPLES, EXAMPLES, corpus_params
from util import assert_harness_parity as assert_parity, harness_render_ours as _ours, scoreboard_elements, write_doc


# Every element of MaterialX's Examples is at parity except the differences listed, with their reasons and
# images, in docs/differences/README.md. The chess set is left out for time (seconds per draw on llvmpipe).
DIFFERENCES = {"open_pbr_honey.mtlx", "standard_surface_onyx_hextiled.mtlx"}
# sRGB-encoded texture files: compared with MaterialX's colour management on (the scoreboard's reference has
# none and reads the files raw; see docs/differences).
COLOR_MANAGED = {"standard_surface_greysphere_calibration.mtlx", "standard_surface_wood_tiled.mtlx",
                 "standard_surface_look_wood_tiled.mtlx"}


def _all_examples():
    import glob
    for path, element in scoreboard_elements(sorted(glob.glob(os.path.join(EXAMPLES, "*", "*.mtlx")))):
        name = os.path.basename(path)
        if "chess_set" not in name and name not in DIFFERENCES:
            yield pytest.param(path, element, id="%s:%s" % (name, element))


@pytest.mark.corpus
@pytest.mark.parametrize("path, element", corpus_params(_all_examples, width=2))
def test_every_example_at_parity(harness, reference, cms_reference, path, element):
    cms = os.path.basename(path) in COLOR_MANAGED
    assert_parity(harness, cms_reference if cms else reference, path, element)


def test_zero_weight_sheen_is_not_nan(harness):
    # gltf_pbr normalizes sheen_color by its maximum: 0 / 0 when sheen is off; the lobe's weight is 0
    img = _ours(harness, os.path.join(DATA_EXAMPLES, "GltfPbr", "gltf_pbr_default.mtlx"), "Default")
    assert np.isfinite(img).all()
    assert img[..., :3].max() > 0.05


def _surface(bsdf):
    return ('<nodegraph name="g">%s<surface name="s" type="surfaceshader"><input name="bsdf" type="BSDF" '
            'nodename="b"/></surface><output name="out" type="surfaceshader" nodename="s"/></nodegraph>' % bsdf)


def _bsdf(category, node="b", **kw):
    types = {"roughness": "vector2", "ior": "color3" if category == "conductor_bsdf" else "float",
             "scatter_mode": "string", "extinction": "color3", "thinfilm_thickness": "float",
             "thinfilm_ior": "float"}
    return '<%s name="%s" type="BSDF">%s</%s>' % (category, node, "".join(
        '<input name="%s" type="%s" value="%s"/>' % (k, types[k], v) for k, v in kw.items()), category)


THIN_FILM = {
    # phase shifts per polarization and interface: a film of lower and of higher index than the base
    "dielectric_film_below_base": _bsdf("dielectric_bsdf", ior="1.5", roughness="0, 0", scatter_mode="R",
                                        thinfilm_thickness="500", thinfilm_ior="1.3"),
    "dielectric_film_above_base_rough": _bsdf("dielectric_bsdf", ior="1.2", roughness="0.3, 0.3",
                                              scatter_mode="R", thinfilm_thickness="700", thinfilm_ior="1.6"),
    # a conductor base: the complex Fresnel phase of each channel enters its own XYZ component
    "conductor_film": _bsdf("conductor_bsdf", ior="0.2, 0.9, 1.1", extinction="3.9, 2.4, 2.2",
                            roughness="0, 0", thinfilm_thickness="400", thinfilm_ior="1.5"),
}


@pytest.mark.parametrize("name", sorted(THIN_FILM))
def test_thin_film_matches_materialx(harness, reference, tmp_path, name):
    path = write_doc(tmp_path, _surface(THIN_FILM[name]), name=name + ".mtlx")
    assert_parity(harness, reference, path, "g/out")


def test_film_over_ior_one_transmission_matches_materialx(harness, reference, tmp_path):
    # OpenPBR's thin-walled soap bubble in two lobes: a filmed reflection over a transmission of IOR 1.
    # The film does not change what the reflection takes from the layer below, and an interface of IOR 1
    # transmits everything at every angle.
    top = _bsdf("dielectric_bsdf", node="top", ior="1.0", roughness="0, 0", scatter_mode="R",
                thinfilm_thickness="500", thinfilm_ior="1.4")
    base = _bsdf("dielectric_bsdf", node="base", ior="1.0", roughness="0, 0", scatter_mode="T")
    layer = ('<layer name="b" type="BSDF"><input name="top" type="BSDF" nodename="top"/>'
             '<input name="base" type="BSDF" nodename="base"/></layer>')
    path = write_doc(tmp_path, _surface(top + base + layer), name="film_over_t.mtlx")
    assert_parity(harness, reference, path, "g/out")


def test_authored_value_does_not_replace_default_geomprop(harness, reference, tmp_path):
    # MaterialX's generator binds an unconnected input with a defaultgeomprop to the geometry even where
    # the document authors a value (gltf_pbr_default.mtlx sets normal = (0, 0, 1))
    body = _surface('<oren_nayar_diffuse_bsdf name="b" type="BSDF"><input name="normal" type="vector3" '
                    'value="1, 0, 0"/></oren_nayar_diffuse_bsdf>')
    assert_parity(harness, reference, write_doc(tmp_path, body, name="normal_value.mtlx"), "g/out")


def test_onyx_hextiled_at_parity_with_each_draw_fixed(harness, cms_reference, tmp_path):
    """Onyx differs from MaterialX only by its per-tile random numbers (docs/differences): with each range one
    value wide, the same tiles, blend and shading (its colour file is sRGB: MaterialX with its colour management)."""
    src = os.path.join(DATA_EXAMPLES, "StandardSurface", "standard_surface_onyx_hextiled.mtlx")
    fixed = ('<input name="rotationrange" type="vector2" value="40, 40" />'
             '<input name="scalerange" type="vector2" value="1.4, 1.4" />'
             '<input name="offsetrange" type="vector2" value="0.3, 0.3" />')
    text = open(src).read().replace('<input name="falloff" type="float" interfacename="falloff" />',
                                    '<input name="falloff" type="float" interfacename="falloff" />' + fixed)
    text = text.replace('fileprefix="../../../Images/"', 'fileprefix="%s/"' % os.path.abspath(
        os.path.join(DATA_EXAMPLES, "..", "..", "Images")))
    assert text.count("rotationrange") == 2
    path = os.path.join(str(tmp_path), "onyx_fixed.mtlx")
    open(path, "w").write(text)
    assert_parity(harness, cms_reference, path, "M_OnyxHextiled")
