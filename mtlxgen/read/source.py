"""A document from a file: a .mtlx document (document.py) or the materials of a USD stage (usdstage.py)."""
import os

from mtlxgen import is_usd
from mtlxgen.base.diagnostics import Loc, MtlxError
from mtlxgen.read import document


def load_document(path, library_dirs=(), usd_options=None):
    """The Document of a .mtlx file, or of the materials of a USD stage (.usd, .usda, .usdc, .usdz:
    usdstage.py; usd_options a usdstage.StageOptions)."""
    if not os.path.exists(path):
        raise MtlxError((Loc(path, 0), "no such file"))
    if is_usd(path):
        from mtlxgen.read import usdstage
        return usdstage.load(path, library_dirs, usd_options)
    return document.load_upgraded(path, library_dirs)
