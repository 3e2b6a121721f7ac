"""A GGX lobe at the roughness floor in both directions is a mirror to the environment's samplers
(pbrlib/microfacet/ggx.glsl, mg_ggx_is_mirror): one sample along the normal stands for the n samples of its
visible normals, which all fall within 2e-4 rad of the mirror direction. Held here to the sampled estimate (the
same shaders with the mirror test turned off): reflection, refraction (solid and thin-walled), a coat over a
metal, Enterprise PBR's lobe, complete and reduced; and a lobe just above the floor still samples."""
import pytest

from mtlxgen.draw import compare
from mtlxgen import pipeline
from util import write_doc

SURFACES = {
    "dielectric": """<standard_surface name="s" type="surfaceshader">
        <input name="specular_roughness" type="float" value="0" /></standard_surface>""",
    "metal": """<standard_surface name="s" type="surfaceshader"><input name="metalness" type="float" value="1" />
        <input name="base_color" type="color3" value="0.9, 0.6, 0.3" />
        <input name="specular_roughness" type="float" value="0" /></standard_surface>""",
    "glass": """<standard_surface name="s" type="surfaceshader"><input name="transmission" type="float" value="1" />
        <input name="specular_roughness" type="float" value="0" /></standard_surface>""",
    "thin_glass": """<standard_surface name="s" type="surfaceshader"><input name="transmission" type="float" value="1" />
        <input name="thin_walled" type="boolean" value="true" />
        <input name="specular_roughness" type="float" value="0" /></standard_surface>""",
    "coated_metal": """<open_pbr_surface name="s" type="surfaceshader"><input name="base_metalness" type="float" value="1" />
        <input name="specular_roughness" type="float" value="0.4" /><input name="coat_weight" type="float" value="1" />
        <input name="coat_roughness" type="float" value="0" /></open_pbr_surface>""",
    "enterprise": """<enterprise_pbr name="s" type="surfaceshader"><input name="roughness" type="float" value="0" />
        <input name="metallic" type="float" value="1" /></enterprise_pbr>""",
}
MATERIAL = """<surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="s" />
  </surfacematerial>"""
MIRROR_TEST = "return max(alpha.x, alpha.y) <= MG_GGX_ALPHA_MIN;"


def _sampled(shader):
    """The shader with the mirror test off: every lobe takes its u_envRadianceSamples samples."""
    assert MIRROR_TEST in shader.fragment
    shader.fragment = shader.fragment.replace(MIRROR_TEST, "return false;")
    return shader


@pytest.mark.parametrize("interface", ["complete", "reduced"])
@pytest.mark.parametrize("surface", sorted(SURFACES))
def test_a_mirror_takes_one_sample_for_the_same_picture(tmp_path, renderer, surface, interface):
    path = write_doc(tmp_path, SURFACES[surface] + MATERIAL)
    (one,) = pipeline.generate(path, elements=["m"], interface=interface)
    (sampled,) = pipeline.generate(path, elements=["m"], interface=interface)
    p = compare.parity(renderer.render(one), renderer.render(_sampled(sampled)))
    assert p.mean <= 0.05 and p.max <= 2, (surface, interface, p)        # /255


def test_a_lobe_above_the_floor_samples(tmp_path, renderer):
    """roughness 0.02 (alpha 4e-4): not a mirror; its samples spread over neighbouring texels."""
    path = write_doc(tmp_path, SURFACES["metal"].replace('name="specular_roughness" type="float" value="0"',
                                                        'name="specular_roughness" type="float" value="0.02"')
                     + MATERIAL)
    (shader,) = pipeline.generate(path, elements=["m"])
    before = renderer.render(shader)
    shader.fragment = shader.fragment.replace(MIRROR_TEST, "return true;")          # forced to one sample
    assert compare.parity(before, renderer.render(shader)).mean > 0.0
