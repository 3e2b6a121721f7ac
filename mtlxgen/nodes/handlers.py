"""The few node implementations that need code rather than a template.

Each handler takes (node, emitter) and returns {output name: GLSL expression}. A handler is pure: it
writes its statements through the emitter (em.line, at the emitter's indentation) and changes nothing of
the graph; the uniforms a shader gains or leaves out (a UDIM tile's sampler, a <UDIM> pattern that is no
file) go through the emitter's own uniform table (em.add_uniform, em.drop_unread_uniform).
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


# ---------------------------------------------------------------- textures (stdlib_texture.py, cmlib.py)
import os as _os
import re as _re

_ADDRESS_MODES = ("constant", "clamp", "periodic", "mirror")
_FILTER_TYPES = ("closest", "linear", "cubic")
_TAKE = {"float": "{}.r", "vector2": "{}.rg", "color3": "{}.rgb", "vector3": "{}.rgb", "color4": "{}", "vector4": "{}"}
_WIDEN = {"float": "vec4(vec3({}), 1.0)", "vector2": "vec4({}, 0.0, 1.0)", "color3": "vec4({}, 1.0)",
          "vector3": "vec4({}, 1.0)", "color4": "{}", "vector4": "{}"}
_TILE_TOKENS = _re.compile(r"<UDIM>|<UVTILE>")


def _texture_file(node, em, name="file"):
    """(sampler uniform, file value, colour space) of a filename input."""
    src = node.inputs[name]
    sampler = src.uniform or (em.expr(src) if src.linked else None)
    u = em.uniform(sampler)
    if u is None:
        em.fail(node, "input '%s' does not name a texture file" % name)
    return sampler, str(u.value or ""), src.colorspace or u.colorspace


def _color_managed(em, expr, out_type, colorspace):
    """The read converted from the file's colour space to the working space (colour types only).

    As MaterialX: the working space is the document's `colorspace`; a document declaring none, or one
    other than lin_rec709 (cmlib converts only to lin_rec709), reads its files unconverted."""
    from mtlxgen.nodes import cmlib
    t = None
    if out_type in ("color3", "color4") and cmlib.is_working_space(em.graph.colorspace):
        t = cmlib.transform(colorspace)
    if t is None:
        return expr
    files, template = t
    for f in files:
        em.require(f)
    if out_type == "color3":
        return template.format(c=expr)
    var = em.fresh("cm")
    em.line("vec4 %s = %s;" % (var, expr))
    return "vec4(%s, %s.a)" % (template.format(c=var + ".rgb"), var)


def _static_choice(node, em, name, allowed, fallback):
    value = node.static.get(name) or fallback
    if value not in allowed:
        em.fail(node, "%s '%s' is not one of %s" % (name, value, ", ".join(allowed)))
    return value


def _default_value(node, name="default"):
    v = node.inputs[name].value if name in node.inputs and not node.inputs[name].linked else None
    if isinstance(v, tuple):
        return list(v)
    return v


def _udim_tiles(node, em, sampler, value, colorspace):
    """{(u, v) cell: new sampler uniform} for a file naming <UDIM> or <UVTILE>, one per tile on disk."""
    from mtlxgen.base.resolve import resolve_file
    folder, base = _os.path.split(value)
    where = resolve_file(folder or ".", em.graph.doc_path)
    if where is None or not _os.path.isdir(where):
        return {}
    parts = _TILE_TOKENS.split(base)
    tokens = _TILE_TOKENS.findall(base)
    pattern = "".join(_re.escape(p) + ("(?P<t%d>%s)" % (i, r"\d{4}" if tokens[i] == "<UDIM>" else r"u\d+_v\d+")
                                      if i < len(tokens) else "") for i, p in enumerate(parts))
    tiles = {}
    for f in sorted(_os.listdir(where)):
        m = _re.fullmatch(pattern, f)
        if not m:
            continue
        t = m.group("t0")
        if t.isdigit():
            n = int(t) - 1001
            cell = (n % 10, n // 10)
        else:
            uu, vv = t[1:].split("_v")
            cell = (int(uu) - 1, int(vv) - 1)
        if cell in tiles:
            continue
        tiles[cell] = em.add_uniform("%s_%s" % (sampler, t), "filename", _os.path.join(where, f), node.loc, colorspace)
    return tiles


def image(node, em):
    """image: a texture read at texcoord, typed, colour-managed; tiled files (UDIM) one sampler per tile."""
    out_type = node.outputs["out"]
    sampler, value, colorspace = _texture_file(node, em)
    uv = em.input_expr(node, "texcoord")
    sampling = {"uaddressmode": _static_choice(node, em, "uaddressmode", _ADDRESS_MODES, "periodic"),
                "vaddressmode": _static_choice(node, em, "vaddressmode", _ADDRESS_MODES, "periodic"),
                "filtertype": _static_choice(node, em, "filtertype", _FILTER_TYPES, "linear"),
                "default": _default_value(node)}
    # layer, framerange, frameoffset and frameendaction name frames of image sequences: one frame is read
    if _TILE_TOKENS.search(value):
        tiles = _udim_tiles(node, em, sampler, value, colorspace)
        if not tiles:
            em.fail(node, "no tiles of '%s' found on disk" % value)
        em.require("stdlib/texture/udim.glsl")
        uvar, cell = em.fresh("%s_uv" % node.id), em.fresh("%s_tile" % node.id)
        em.line("vec2 %s = %s;" % (uvar, uv))
        em.line("ivec2 %s = ivec2(floor(%s));" % (cell, uvar))
        read = _WIDEN[out_type].format(em.input_expr(node, "default"))
        for (cu, cv), tile in sorted(tiles.items(), reverse=True):
            em.textures[tile] = dict(sampling)
            read = "(%s == ivec2(%d, %d) ? mg_udim_read(%s, %s, %s) : %s)" % (cell, cu, cv, tile, uvar, cell, read)
        em.drop_unread_uniform(sampler, node)     # the <UDIM> pattern itself is no file
    else:
        em.textures[sampler] = sampling
        read = "texture(%s, %s)" % (sampler, uv)
    return {"out": _color_managed(em, _TAKE[out_type].format(read), out_type, colorspace)}


def hextiledimage(node, em):
    """hextiledimage / hextilednormalmap: hex-tiling of one texture (Mikkelsen 2022)."""
    out_type = node.outputs["out"]
    sampler, value, colorspace = _texture_file(node, em)
    em.textures[sampler] = {"uaddressmode": "periodic", "vaddressmode": "periodic", "filtertype": "linear",
                            "default": _default_value(node)}
    em.require("stdlib/texture/hextile.glsl")
    args = ", ".join(em.input_expr(node, n) for n in (
        "texcoord", "tiling", "rotation", "rotationrange", "scale", "scalerange", "offset", "offsetrange", "falloff"))
    if node.category == "hextilednormalmap":
        return {"out": "mg_hextilednormalmap(%s, %s, %s, %s, %s, %s, %s)" % (
            sampler, args, em.input_expr(node, "strength"), em.input_expr(node, "flip_g"),
            em.input_expr(node, "normal"), em.input_expr(node, "tangent"), em.input_expr(node, "bitangent"))}
    read = "mg_hextiledimage(%s, %s, %s, %s)" % (sampler, args, em.input_expr(node, "falloffcontrast"),
                                                   em.input_expr(node, "lumacoeffs"))
    return {"out": _color_managed(em, _TAKE[out_type].format(read), out_type, colorspace)}
