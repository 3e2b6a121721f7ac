"""The environment method's code only in the shaders that use it: MG_ENV_PREFILTERED and MG_REFRACTION_PREFILTERED
are glsldeps paste switches, resolved per method where glsl_lib code is pasted (emit.emitter.ENVIRONMENT_SWITCHES).
A fis shader holds none of the split sum's lookup, a prefiltered one none of the sampling loops, for every target
(and the reference compiler accepts both); the prefiltered shader draws the pixels of the one the preprocessor
resolved (both branches pasted, the names #defined: how shaders were written before)."""
import numpy as np
import pytest

from mtlxgen import pipeline
from mtlxgen.base import targets
from mtlxgen.emit import emitter as emit, glsldeps
from util import write_doc

# reflection (a rough anisotropic metal coat), refraction (transmission) and the Enterprise PBR lobe: the three
# glsl_lib files with a branch per method
DOC = """
  <standard_surface name="ss" type="surfaceshader">
    <input name="metalness" type="float" value="0.5" />
    <input name="specular_roughness" type="float" value="0.35" />
    <input name="specular_anisotropy" type="float" value="0.6" />
    <input name="transmission" type="float" value="0.5" />
  </standard_surface>
  <surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="ss" />
  </surfacematerial>
  <enterprise_pbr name="ep" type="surfaceshader"><input name="anisotropy" type="float" value="0.5" />
  </enterprise_pbr>
  <surfacematerial name="e" type="material"><input name="surfaceshader" type="surfaceshader" nodename="ep" />
  </surfacematerial>"""

PREFILTERED_ONLY = ("mg_env_prefiltered_lobe", "mg_env_lod_prefiltered")
FIS_ONLY = ("mg_env_specular_samples", "mg_env_refraction_samples", "mg_env_lod_base")
SWITCH_NAMES = ("MG_ENV_PREFILTERED", "MG_REFRACTION_PREFILTERED")


def _generate(path, environment, target="glsl", interface="complete"):
    return {s.element: s for s in pipeline.generate(path, environment=environment, target=target,
                                                    interface=interface)}


@pytest.mark.parametrize("interface", ["complete", "reduced"])
@pytest.mark.parametrize("target", targets.NAMES)
def test_each_method_pastes_its_own_code_only(tmp_path, target, interface):
    path = write_doc(tmp_path, DOC)
    fis, pre = _generate(path, "fis", target, interface), _generate(path, "prefiltered", target, interface)
    assert set(fis) == set(pre) == {"m", "e"}
    for element in ("m", "e"):
        f, p = glsldeps.compact(fis[element].fragment), glsldeps.compact(pre[element].fragment)
        assert fis[element].manifest["environment"] == "fis" and pre[element].manifest["environment"] == "prefiltered"
        assert not [name for name in PREFILTERED_ONLY + SWITCH_NAMES if name in f], (target, element)
        assert "mg_env_prefiltered_lobe" in p and not [name for name in FIS_ONLY + SWITCH_NAMES if name in p]
        assert "mg_env_sample_point" in f and "mg_env_sample_point" not in p     # the Hammersley points too
        assert len(f) < len(fis[element].fragment) or interface == "reduced"
    # refraction: the prefiltered lookup along the refracted direction, the sampled loop in fis
    assert "mg_env_lod_prefiltered(" in glsldeps.compact(pre["m"].fragment)
    assert "mg_env_refraction_samples(" in glsldeps.compact(fis["m"].fragment)


@pytest.mark.gl                     # glslangValidator
@pytest.mark.parametrize("target", targets.NAMES)
def test_both_methods_are_valid_to_the_reference_compiler(tmp_path, target):
    from mtlxgen.apps.glslvalidate import GLSLANG, validate
    if GLSLANG is None:
        pytest.skip("glslangValidator not installed (Debian glslang-tools)")
    path = write_doc(tmp_path, DOC)
    for environment in ("fis", "prefiltered"):
        for s in _generate(path, environment, target).values():
            assert validate(s, str(tmp_path), target) == [], (environment, s.element)


def test_library_code_by_hand_keeps_the_directives():
    """emit.lib_source pastes whole files: the directives stay, the names undefined (the fis branch compiles)."""
    text = emit.lib_source(["lighting/environment_specular.glsl"])
    assert "#ifdef MG_ENV_PREFILTERED" in text and "mg_env_specular_samples" in text


def _preprocessed_prefiltered(path, monkeypatch):
    """The prefiltered shaders as they were written before the switches: both methods' code pasted (no switch
    resolved for the method), the names #defined after the #version line."""
    with monkeypatch.context() as m:
        m.setattr(emit, "ENVIRONMENT_SWITCHES", dict(emit.ENVIRONMENT_SWITCHES, prefiltered=frozenset()))
        m.setattr(glsldeps, "SWITCHES", tuple(n for n in glsldeps.SWITCHES if n not in SWITCH_NAMES))
        m.setattr(glsldeps, "_RESOLVED", {})        # (resolutions kept per process: made under the switches)
        m.setattr(glsldeps, "_SWITCHED", {})
        shaders = _generate(path, "prefiltered")
    for s in shaders.values():
        first, _, rest = s.fragment.partition("\n")
        s.fragment = "\n".join([first] + ["#define " + n for n in SWITCH_NAMES] + [rest])
        assert "#ifdef MG_ENV_PREFILTERED" in s.fragment and "mg_env_prefiltered_lobe" in s.fragment
        assert "mg_env_specular_samples" in s.fragment or "mg_env_lod_base" in s.fragment
    return shaders


def test_prefiltered_pixels_are_those_the_preprocessor_resolved(tmp_path, renderer, monkeypatch):
    path = write_doc(tmp_path, DOC)
    switched = _generate(path, "prefiltered")
    before = _preprocessed_prefiltered(path, monkeypatch)
    for element in ("m", "e"):
        assert len(switched[element].fragment) < len(before[element].fragment)
        a, b = renderer.render(switched[element]), renderer.render(before[element])
        assert np.array_equal(a, b, equal_nan=True), (element, float(np.nanmax(np.abs(a - b))))
        assert float(np.nanmax(a[..., :3])) > 0.05          # something lit drawn
