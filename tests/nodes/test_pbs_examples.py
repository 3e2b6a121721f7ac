"""The bundled MaterialX PBS-node examples (examples/pbs) against MaterialX's own GLSL in our harness."""
import os

import pytest

from util import assert_parity_with_materialx

PBS = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "examples", "pbs", "pbs_nodes.mtlx")


@pytest.mark.parametrize("material", ["coated_plastic", "brushed_gold", "iridescent_steel", "translucent_velvet"])
def test_pbs_example_matches_materialx(renderer, reference, material):
    assert_parity_with_materialx(renderer, reference, PBS, material)


def test_opacity_reaches_the_output_alpha(renderer):
    from mtlxgen import pipeline
    img = renderer.render(pipeline.generate(PBS, elements=["translucent_velvet"])[0])
    covered = img[..., 3] > 0
    assert abs(float(img[covered][:, 3].mean()) - 0.8) < 0.01
