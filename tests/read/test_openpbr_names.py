"""open_pbr_surface documents written against the 2023 draft input names get one clear line naming the
released input (mtlxgen/read/renamed_inputs.py), through the CLI."""
import os
import subprocess
import sys

import pytest

from mtlxgen.read.renamed_inputs import OPEN_PBR_DRAFT
from tests.util import write_doc

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _doc(tmp_path, inputs):
    return write_doc(tmp_path, """
  <open_pbr_surface name="pbr" type="surfaceshader">%s
  </open_pbr_surface>
  <surfacematerial name="mat" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="pbr" />
  </surfacematerial>""" % "".join('\n    <input name="%s" type="%s" value="%s" />' % i for i in inputs))


def _cli(*args):
    return subprocess.run([sys.executable, os.path.join(ROOT, "cli.py")] + list(args), capture_output=True, text=True)


def test_coat_IOR_names_coat_ior(tmp_path):
    path = _doc(tmp_path, [("base_color", "color3", "0.8, 0.2, 0.1"), ("coat_IOR", "float", "1.5")])
    r = _cli("generate", path, "-o", str(tmp_path / "out"))
    assert r.returncode == 1 and "Traceback" not in r.stderr
    assert r.stderr.strip().splitlines() == [
        "%s:6: open_pbr_surface input 'coat_IOR' is the 2023 draft name; the released input is 'coat_ior'" % path]


def test_each_draft_input_gets_its_own_line(tmp_path):
    path = _doc(tmp_path, [("fuzz", "float", "0.5"), ("emission_weight", "float", "1"),
                           ("specular_anisotropy", "float", "0.2")])
    r = _cli("render", path, "-o", str(tmp_path / "out"))
    assert r.returncode == 1
    lines = r.stderr.strip().splitlines()
    assert lines == ["%s:%d: open_pbr_surface input '%s' is the 2023 draft name; the released input is '%s'"
                     % (path, line, old, new) for line, old, new in
                     ((5, "fuzz", "fuzz_weight"), (6, "emission_weight", "emission_luminance"),
                      (7, "specular_anisotropy", "specular_roughness_anisotropy"))]


def test_draft_input_without_a_released_counterpart_says_so(tmp_path):
    path = _doc(tmp_path, [("specular_rotation", "float", "0.25")])
    r = _cli("generate", path, "-o", str(tmp_path / "out"))
    assert r.returncode == 1
    assert r.stderr.strip() == ("%s:5: open_pbr_surface input 'specular_rotation' is the 2023 draft name; the "
                                "released node has no such input; orient the anisotropy with geometry_tangent" % path)


def test_released_names_are_all_real_inputs(library):
    nd = library.nodedefs["ND_open_pbr_surface_surfaceshader"]
    for old, new in OPEN_PBR_DRAFT.items():
        assert old not in nd.inputs, old
        assert new is None or new in nd.inputs, (old, new)


def test_unknown_non_draft_input_keeps_the_generic_message(tmp_path):
    path = _doc(tmp_path, [("bogus_input", "float", "1")])
    r = _cli("generate", path, "-o", str(tmp_path / "out"))
    assert r.returncode == 1 and "draft name" not in r.stderr and "bogus_input" in r.stderr


@pytest.mark.parametrize("released", ["coat_ior", "fuzz_weight"])
def test_released_names_still_generate(tmp_path, released):
    path = _doc(tmp_path, [(released, "float", "0.5")])
    r = _cli("generate", path, "-o", str(tmp_path / "out"))
    assert r.returncode == 0, r.stderr
