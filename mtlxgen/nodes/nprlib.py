"""nprlib nodes (MaterialX Specification 1.39, "NPR nodes"): view-dependent shading without lights.

facingratio and gooch_shade are nodegraphs in the data library; they read viewdirection, the one
leaf, which needs the camera position (u_viewPosition), so it is a handler.
"""

NODES = {
    "viewdirection": {"handler": "viewdirection"},
}
