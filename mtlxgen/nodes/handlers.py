"""The few node implementations that need code rather than a template.

Each handler takes (node, emitter) and returns {output name: GLSL expression}.
"""

_SPACES = {"model": "object", "object": "object", "world": "world"}


def _space(node, em, name="space"):
    value = node.static.get(name, "object") or "object"
    if value not in _SPACES:
        em.fail(node, "unknown space '%s' (expected model, object or world)" % value)
    return _SPACES[value]


def geometric(node, em):
    """position / normal / tangent / bitangent in a space; texcoord and geomcolor by index."""
    cat, out_type = node.category, node.outputs["out"]
    if cat in ("position", "normal", "tangent", "bitangent"):
        return {"out": em.stream("%s_%s" % (cat, _space(node, em)))}
    index = int(em.static(node, "index") or 0)
    if cat == "texcoord":
        uv = em.stream("texcoord_%d" % index)
        return {"out": "vec3(%s, 0.0)" % uv if out_type == "vector3" else uv}
    if cat == "geomcolor":
        c = em.stream("color_%d" % index)
        return {"out": {"float": "%s.r", "color3": "%s.rgb"}.get(out_type, "%s") % c}
    em.fail(node, "not a geometric node")


def geompropvalue(node, em):
    """A named primvar: vertex attribute i_geomprop_NAME (uniform string/filename ones fall back to default)."""
    name = em.static(node, "geomprop")
    out_type = node.outputs["out"]
    if node.category == "geompropvalueuniform" or out_type in ("string", "filename") or not name:
        return {"out": em.input_expr(node, "default")}      # no primvar named: the default value
    return {"out": em.stream("geomprop_" + name, out_type)}


def viewdirection(node, em):
    """nprlib viewdirection: the unit direction from the camera to the shaded point, in a space."""
    v = "normalize(%s - %s)" % (em.stream("position_world"), em.app_uniform("u_viewPosition"))
    if _space(node, em) == "object":
        v = "normalize((%s * vec4(%s, 0.0)).xyz)" % (em.app_uniform("u_worldInverseMatrix"), v)
    return {"out": v}


# object <-> world with the application's matrices; normals use the inverse transpose
_TRANSFORMS = {
    ("transformpoint", "object", "world"): "(u_worldMatrix * vec4({x}, 1.0)).xyz",
    ("transformpoint", "world", "object"): "(u_worldInverseMatrix * vec4({x}, 1.0)).xyz",
    ("transformvector", "object", "world"): "(u_worldMatrix * vec4({x}, 0.0)).xyz",
    ("transformvector", "world", "object"): "(u_worldInverseMatrix * vec4({x}, 0.0)).xyz",
    ("transformnormal", "object", "world"): "normalize((u_worldInverseTransposeMatrix * vec4({x}, 0.0)).xyz)",
    ("transformnormal", "world", "object"): "normalize((transpose(u_worldMatrix) * vec4({x}, 0.0)).xyz)",
}


def transform_space(node, em):
    src, dst = _space(node, em, "fromspace"), _space(node, em, "tospace")
    x = em.input_expr(node, "in")
    if src == dst:
        return {"out": x}
    template = _TRANSFORMS[(node.category, src, dst)]
    for u in ("u_worldMatrix", "u_worldInverseMatrix", "u_worldInverseTransposeMatrix"):
        if u in template:
            em.app_uniform(u)
    return {"out": template.format(x=x)}
