"""stdlib geometric nodes (MaterialX Specification 1.39, "Geometric Nodes"): reads of vertex streams.

Spaces: "model" and "object" read the mesh's own frame, "world" applies u_worldMatrix (normals its
inverse transpose). The stream table is in mtlxgen/base/streams.py.
"""

NODES = {
    "position": {"handler": "geometric"},
    "normal": {"handler": "geometric"},
    "tangent": {"handler": "geometric"},
    "bitangent": {"handler": "geometric"},
    "texcoord": {"handler": "geometric"},
    "geomcolor": {"handler": "geometric"},
    "geompropvalue": {"handler": "geompropvalue"},
    "geompropvalueuniform": {"handler": "geompropvalue"},
}
