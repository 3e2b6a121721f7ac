"""Environment integration method (`--environment fis|prefiltered`): filtered importance sampling by
default, the split-sum prefiltered lookup as the option. The two must agree where the lobe is a mirror
and stay close on rough lobes; shaders and manifests say which one they use."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from mtlxgen.draw import compare
from mtlxgen import pipeline
from util import write_doc

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

DOC = """
  <standard_surface name="ss" type="surfaceshader">
    <input name="base_color" type="color3" value="0.6, 0.3, 0.2" />
    <input name="metalness" type="float" value="{metal}" />
    <input name="specular_roughness" type="float" value="{rough}" />
    <input name="transmission" type="float" value="{transmission}" />
  </standard_surface>
  <surfacematerial name="m" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="ss" />
  </surfacematerial>
"""


def _pair(renderer, tmp_path, **kw):
    args = dict(metal=1.0, rough=0.0, transmission=0.0)
    args.update(kw)
    path = write_doc(tmp_path, DOC.format(**args))
    images = []
    for method in ("fis", "prefiltered"):
        (shader,) = pipeline.generate(path, elements=["m"], environment=method)
        images.append(renderer.render(shader))
    return images


def test_prefiltered_shader_is_marked(tmp_path):
    path = write_doc(tmp_path, DOC.format(metal=1.0, rough=0.3, transmission=0.0))
    (fis,) = pipeline.generate(path, elements=["m"])
    (pre,) = pipeline.generate(path, elements=["m"], environment="prefiltered")
    assert "mg_env_prefiltered_lobe(" in pre.fragment and "mg_env_prefiltered_lobe" not in fis.fragment
    assert fis.manifest["environment"] == "fis" and pre.manifest["environment"] == "prefiltered"


def test_unlit_shader_has_no_environment_field(tmp_path):
    path = write_doc(tmp_path, """
  <constant name="c" type="color3"><input name="value" type="color3" value="1, 0, 0" /></constant>
  <output name="o" type="color3" nodename="c" />""")
    (s,) = pipeline.generate(path, environment="prefiltered")
    assert "environment" not in s.manifest and "MG_ENV_PREFILTERED" not in s.fragment


def test_unknown_method_is_refused(tmp_path):
    path = write_doc(tmp_path, DOC.format(metal=1.0, rough=0.3, transmission=0.0))
    with pytest.raises(ValueError):
        pipeline.generate(path, elements=["m"], environment="bogus")
    r = subprocess.run([sys.executable, os.path.join(ROOT, "cli.py"), "generate", path, "-o", str(tmp_path / "o"),
                        "--environment", "bogus"], capture_output=True, text=True)
    assert r.returncode == 1 and "invalid choice" in r.stderr and "Traceback" not in r.stderr


def test_mirror_is_the_same_either_way(renderer, tmp_path):
    fis, pre = _pair(renderer, tmp_path, rough=0.0)
    p = compare.parity(pre, fis)
    assert p.passes, p


# the wider the lobe, the coarser the single mip level standing in for it (box-filtered levels average
# sky and ground where the lobe would weight them by its shape)
@pytest.mark.parametrize("rough,rtol", [(0.3, 0.05), (0.7, 0.15)])
def test_rough_lobes_stay_close(renderer, tmp_path, rough, rtol):
    fis, pre = _pair(renderer, tmp_path, rough=rough)
    mask = fis[..., 3] > 0.99
    # the same energy (albedo from the same table), the lobe's shape approximated by one mip level
    mean_fis, mean_pre = fis[mask][:, :3].mean(0), pre[mask][:, :3].mean(0)
    assert np.allclose(mean_pre, mean_fis, rtol=rtol), (mean_pre, mean_fis)
    assert np.abs(pre - fis)[mask][:, :3].mean() < 0.03
    # and it really is a different integration (the option is not ignored)
    assert np.abs(pre - fis)[mask][:, :3].max() > 1.0 / 255


def test_rough_transmission_prefiltered_keeps_the_sampled_energy(renderer, tmp_path):
    fis, pre = _pair(renderer, tmp_path, metal=0.0, rough=0.4, transmission=1.0)
    mask = fis[..., 3] > 0.99
    assert np.allclose(pre[mask][:, :3].mean(0), fis[mask][:, :3].mean(0), rtol=0.05)
    assert np.abs(pre - fis)[mask][:, :3].max() > 1.0 / 255      # the refracted lobe is prefiltered too


def test_cli_option_writes_prefiltered_shaders(tmp_path):
    path = write_doc(tmp_path, DOC.format(metal=1.0, rough=0.3, transmission=0.0))
    out = tmp_path / "o"
    r = subprocess.run([sys.executable, os.path.join(ROOT, "cli.py"), "generate", path, "-o", str(out),
                        "--environment", "prefiltered"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert json.loads((out / "m.json").read_text())["environment"] == "prefiltered"
    assert "mg_env_prefiltered_lobe(" in (out / "m.frag").read_text()
