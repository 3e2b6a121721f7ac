"""Helpers for tests: write a document, generate it, render ours and MaterialX's, compare."""
import functools
import os

import numpy as np

from mtlxgen.draw import compare
from mtlxgen.read import document
from mtlxgen.base import images
from mtlxgen import pipeline

FAILURES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "_failures")


def write_doc(tmp_path, body, name="doc.mtlx", version="1.39"):
    path = os.path.join(str(tmp_path), name)
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<materialx version="%s">\n%s\n</materialx>\n' % (version, body))
    return path


def build_graph(tmp_path, body, element, library):
    """The typed Graph of one element of a document written from `body`."""
    return pipeline.build_graph(document.load(write_doc(tmp_path, body)), library, element)


def generate_one(path, element=None):
    shaders = pipeline.generate(path, elements=[element] if element else None)
    return shaders[0] if element else shaders


def save_side_by_side(name, ours, theirs):
    """Write ours | theirs | diff for a failing comparison; returns the path."""
    os.makedirs(FAILURES, exist_ok=True)
    a, b = images.to_srgb8(ours)[..., :3], images.to_srgb8(theirs)[..., :3]
    diff = np.abs(a.astype(np.int16) - b.astype(np.int16)).max(-1)
    heat = np.stack([np.clip(diff * 8, 0, 255)] * 3, -1).astype(np.uint8)
    path = os.path.join(FAILURES, name.replace("/", "_") + ".png")
    images.write_image(path, np.concatenate([a, b, heat], axis=1))
    return path


def bsdf_material(body, bsdf="b"):
    """MaterialX elements `body` plus a surface `s` over its BSDF node `bsdf` and a surfacematerial `m`."""
    return body + ('<surface name="s" type="surfaceshader"><input name="bsdf" type="BSDF" nodename="%s" /></surface>'
                   '<surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" '
                   'nodename="s" /></surfacematerial>' % bsdf)


def render_with_materialx(renderer, reference, path, element):
    """(ours, MaterialX's) renders of one element, both drawn by `renderer` (our harness, any environment)."""
    ours = renderer.render(generate_one(path, element))
    vs, fs, tex, _ = reference.generate(path, element)
    theirs, _ = renderer.render_timed(vs, fs, {}, tex)
    return ours, theirs


def assert_parity_with_materialx(renderer, reference, path, element):
    """Render our shader and MaterialX's for one element in our harness and assert parity."""
    ours, theirs = render_with_materialx(renderer, reference, path, element)
    p = compare.parity(ours, theirs)
    if not p.passes:
        where = save_side_by_side(os.path.basename(path) + "_" + element, ours, theirs)
        raise AssertionError("%s %s: %s (side by side: %s)" % (os.path.basename(path), element, p, where))
    return p


def harness_render_ours(harness, path, element):
    """Our shader for one element drawn by `harness` (a Renderer in the scoreboard's scene) as the scoreboard
    draws it: texture files bound by uniform name, no default colours for unreadable ones."""
    shader = pipeline.generate(path, elements=[element])[0]
    img, _ = harness.render_timed(shader.vertex, shader.fragment, None,
                                  {t["uniform"]: t["file"] for t in shader.manifest["textures"]})
    return img


def assert_harness_parity(harness, reference, path, element, theirs_shader=None):
    """Ours and MaterialX's for one element, both drawn in the scoreboard's scene (conftest's `harness`), at
    parity. theirs_shader: MaterialX's (vertex, fragment, textures, seconds) when the caller generated it already."""
    vs, fs, tex, _ = theirs_shader or reference.generate(path, element)
    ours = harness_render_ours(harness, path, element)
    theirs, _ = harness.render_timed(vs, fs, None, tex)
    p = compare.parity(ours, theirs)
    if not p.passes:
        where = save_side_by_side(os.path.basename(path) + "_" + element.replace("/", "_"), ours, theirs)
        raise AssertionError("%s: %s (side by side: %s)" % (element, p, where))


@functools.lru_cache(maxsize=1)
def _element_lister():
    from mtlxgen.apps.reference import MaterialXReference
    return MaterialXReference()


def scoreboard_elements(paths):
    """(path, element) for each element MaterialX finds renderable in each file, as the scoreboard counts
    them; files MaterialX cannot read are not counted (the scoreboard skips them too). Without the
    materialx wheel this raises: parity must be checked."""
    ref = _element_lister()
    pairs = []
    for path in paths:
        try:
            elements = ref.elements(path)
        except Exception:       # e.g. look_brass_tiled includes a file the corpus lacks
            continue
        pairs += [(path, element) for element in elements]
    return pairs
