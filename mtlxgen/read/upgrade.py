"""Bring older documents up to 1.39 semantics, on the XML element tree, before the document is built.

MaterialX reads any older document as the 1.39 document it stands for; so do we. Each step below
rewrites the syntax one release retired into what replaced it, and names that release. Steps run in
version order on documents older than the step, so a 1.22 document passes through all of them. The
rewrite keeps every element's file and line, so problems are still reported where they were written.

The rules are taken from the MaterialX changelog and specification of each release, checked against
what MaterialX 1.39 renders for the corpus documents (TestSuite/stdlib/upgrade).
"""
from mtlxgen.read.xmlreader import XElement

LATEST = (1, 39)

# tags of elements that are not nodes (kept in step with document.NON_NODE_TAGS; imported lazily there)
_NOT_NODES = {
    "nodedef", "nodegraph", "opgraph", "implementation", "typedef", "geompropdef", "look", "lookgroup",
    "collection", "geominfo", "propertyset", "propertysetassign", "variantset", "variantassign", "backdrop",
    "unitdef", "unittypedef", "attributedef", "targetdef", "member", "input", "output", "token", "parameter",
    "comment", "materialassign", "visibility", "variant", "geomprop", "property", "unit", "materialx",
    "shader", "material", "shaderref", "override", "bindinput", "bindparam", "bindtoken",
}
_PORTS = ("input", "parameter")
_SIZE = {"float": 1, "integer": 1, "boolean": 1, "color3": 3, "color4": 4, "vector2": 2, "vector3": 3,
         "vector4": 4}
_CHANNEL = {"r": 0, "g": 1, "b": 2, "a": 3, "x": 0, "y": 1, "z": 2, "w": 3}
_SHADER_TYPE = {"surface": "surfaceshader", "volume": "volumeshader", "displacement": "displacementshader",
                "light": "lightshader"}
_MATERIAL_INPUT = {"surfaceshader": "surfaceshader", "volumeshader": "volumeshader",
                   "displacementshader": "displacementshader"}


def version_of(text):
    try:
        return tuple(int(x) for x in (text or "1.39").split("."))
    except ValueError:
        return LATEST


def upgrade_tree(root, warnings=None):
    """Rewrite a <materialx> element tree older than 1.39 in place; returns it (marked 1.39). warnings: a list
    that receives (Loc, message) where the upgrade assumes what an older document meant (as MaterialX does)."""
    v = version_of(root.get("version"))
    if v >= LATEST:
        return root
    for step_version, step in _STEPS:
        if v < step_version:
            step(root, [] if warnings is None else warnings)
    root.attrs["version"] = "%d.%d" % LATEST
    return root


def upgrade(doc):
    """Documents are upgraded as they are built (document.build calls upgrade_tree); kept for callers."""
    return doc


# ---------------------------------------------------------------- tree helpers

def _el(tag, attrs, loc, children=()):
    return XElement(tag, dict(attrs), loc, list(children))


def _is_node(el):
    return el.tag not in _NOT_NODES and not el.tag.startswith("xi:")


def _scopes(root):
    """The document and each nodegraph: the containers whose children are nodes."""
    yield root
    for c in root.children:
        if c.tag in ("nodegraph", "opgraph"):
            yield c


def _nodes(scope):
    return [c for c in scope.children if _is_node(c)]


def _ports(el):
    return [c for c in el.children if c.tag in _PORTS]


def _port(el, name):
    for c in el.children:
        if c.tag in _PORTS and c.get("name") == name:
            return c
    return None


def _find(scope, name, node_only=True):
    for c in scope.children:
        if c.get("name") == name and (_is_node(c) or not node_only):
            return c
    return None


class _Namer:
    """Fresh element names in one scope: stem, stem2, stem3, ..."""

    def __init__(self, scope):
        self.used = {c.get("name") for c in scope.children}

    def __call__(self, stem):
        name, k = stem, 1
        while name in self.used:
            k += 1
            name = "%s%d" % (stem, k)
        self.used.add(name)
        return name


def _connection(port):
    return {k: port.attrs[k] for k in ("nodename", "nodegraph", "output", "interfacename") if k in port.attrs}


def _set_connection(port, conn):
    for k in ("nodename", "nodegraph", "output", "interfacename", "value"):
        port.attrs.pop(k, None)
    port.attrs.update(conn)


def _rename_port(el, old, new):
    p = _port(el, old)
    if p is not None:
        p.attrs["name"] = new
    return p


# ---------------------------------------------------------------- values

def _components(type_name, text):
    if type_name in ("float", "integer", "boolean"):
        return [text.strip()]
    return [s.strip() for s in text.split(",")]


def _number(text):
    return "1" if text == "true" else "0" if text == "false" else text


def _source_type(root, scope, port):
    """The type of what feeds `port`, where the document says (None where it does not)."""
    if "nodename" in port.attrs:
        node = _find(scope, port.get("nodename"))
        if node is None:
            return None
        if node.get("type") != "multioutput":
            return node.get("type")
        out = port.get("output")
        for c in node.children:
            if c.tag == "output" and c.get("name") == out:
                return c.get("type")
        return None
    if "nodegraph" in port.attrs:
        g = _find(root, port.get("nodegraph"), node_only=False)
        if g is None:
            return None
        outs = [c for c in g.children if c.tag == "output"]
        for c in outs:
            if c.get("name") == port.get("output") or len(outs) == 1:
                return c.get("type")
        return None
    if "interfacename" in port.attrs and scope is not root:
        p = _port(scope, port.get("interfacename"))
        if p is not None:
            return p.get("type")
        nd = _find(root, scope.get("nodedef"), node_only=False)
        p = _port(nd, port.get("interfacename")) if nd is not None else None
        return p.get("type") if p is not None else None
    return None


# ---------------------------------------------------------------- swizzles (channels, <swizzle>)

def _swizzle(scope, namer, loc, source, src_type, channels, dst_type, name=None):
    """Nodes computing `channels` of `source` as dst_type, in 1.39 vocabulary (extract, convert,
    combineN, constant, dot). source: {"value": text} or a connection dict. Returns the connection
    (or {"value": ...}) that now carries the result; with `name`, the result node gets that name."""
    n = _SIZE.get(dst_type, 1)
    channels = (channels or "")[:n].ljust(n, "r")       # channels not named read the first one
    picks = []
    for ch in channels:
        picks.append(("const", ch) if ch in "01" else ("chan", _CHANNEL.get(ch.lower(), 0)))
    if "value" in source:
        comps = _components(src_type, source["value"])
        out = [p[1] if p[0] == "const" else _number(comps[min(p[1], len(comps) - 1)]) for p in picks]
        value = ", ".join(out)
        if name is None:
            return {"value": value}
        scope.children.append(_el("constant", {"name": name, "type": dst_type}, loc,
                                  [_el("input", {"name": "value", "type": dst_type, "value": value}, loc)]))
        return {"nodename": name}
    new = []

    def node(tag, stem, type_name, inputs, exact=False):
        nm = stem if exact else namer(stem)
        new.append(_el(tag, {"name": nm, "type": type_name}, loc,
                       [_el("input", dict(name=k, type=t, **a), loc) for k, t, a in inputs]))
        return nm

    src_size = _SIZE.get(src_type, 1)

    extracts = {}

    def component(pick):
        if pick[0] == "const":
            return {"value": pick[1]}
        if src_size == 1:
            return dict(source)
        if pick[1] not in extracts:
            extracts[pick[1]] = node("extract", "extract", "float",
                                     [("in", src_type, source), ("index", "integer", {"value": str(pick[1])})])
        return {"nodename": extracts[pick[1]]}

    identity = all(p[0] == "chan" and p[1] == i for i, p in enumerate(picks))
    if n == 1 and picks[0][0] == "const":
        tag, inputs = "constant", [("value", "float", {"value": picks[0][1]})]
    elif n == 1 and src_size == 1:
        tag, inputs = "dot", [("in", src_type, source)]
    elif n == 1:
        tag, inputs = "extract", [("in", src_type, source), ("index", "integer", {"value": str(picks[0][1])})]
    elif src_size == 1 and all(p[0] == "chan" for p in picks):
        tag, inputs = "convert", [("in", src_type, source)]
    elif identity and src_size == n:
        tag, inputs = ("dot" if src_type == dst_type else "convert"), [("in", src_type, source)]
    else:
        tag = "combine%d" % n
        inputs = [("in%d" % (i + 1), "float", component(p)) for i, p in enumerate(picks)]
    node(tag, name or "swizzle", dst_type, inputs, exact=bool(name))
    scope.children.extend(new)
    return {"nodename": new[-1].get("name")}


def _channels_attributes(root):
    """`channels` on an input or output (1.37, 1.38; gone in 1.39): each becomes the swizzle it
    stood for, made of 1.39 nodes."""
    for scope in _scopes(root):
        namer = _Namer(scope)
        for el in list(scope.children):
            ports = [el] if el.tag == "output" else _ports(el) if _is_node(el) else []
            for p in ports:
                channels = p.attrs.pop("channels", None)
                if channels is None:
                    continue
                dst = p.get("type", "float")
                if "value" in p.attrs and not _connection(p):
                    src_type = dst if len(_components(dst, p.get("value"))) > 1 else "float"
                    p.attrs.update(_swizzle(scope, namer, p.loc, {"value": p.get("value")}, src_type,
                                            channels, dst))
                    continue
                src_type = _source_type(root, scope, p) or _guess_type(channels, dst)
                conn = _swizzle(scope, namer, p.loc, _connection(p), src_type, channels, dst)
                _set_connection(p, conn)


def _guess_type(channels, dst):
    """Where the source's type is unknown: the smallest of dst's family holding every channel named."""
    idx = max([_CHANNEL.get(c.lower(), 0) for c in channels if c not in "01"] or [0])
    if idx == 0 and len(set(channels) - set("01")) <= 1 and _SIZE.get(dst, 1) > 1:
        return "float"
    if dst.startswith("color"):
        return "color3" if idx < 3 else "color4"
    return "vector%d" % max(2, idx + 1)


def _swizzle_nodes(root):
    """1.39 removed the <swizzle> node: constant, extract, convert or combine take its place."""
    for scope in _scopes(root):
        namer = _Namer(scope)
        for el in list(scope.children):
            if el.tag != "swizzle":
                continue
            scope.children.remove(el)
            inp = _port(el, "in")
            ch = _port(el, "channels")
            channels = ch.get("value", "") if ch is not None else ""
            dst = el.get("type", "float")
            src_type = inp.get("type", "float") if inp is not None else "float"
            if inp is None:
                source = {"value": ", ".join(["0"] * _SIZE.get(src_type, 1))}
            elif _connection(inp):
                source = _connection(inp)
            else:
                source = {"value": inp.get("value", ", ".join(["0"] * _SIZE.get(src_type, 1)))}
            if source.get("nodename") == el.get("name"):
                source = {"value": "0"}
            _swizzle(scope, namer, el.loc, source, src_type, channels, dst, name=el.get("name"))


# ---------------------------------------------------------------- 1.22 - 1.26: opgraphs, shaders, materials

def _legacy_graphs(root, warnings):
    """opgraph -> nodegraph; outputs that name their node in a child `in` parameter; graphname inputs."""
    for el in root.children:
        if el.tag == "opgraph":
            el.tag = "nodegraph"
    for scope in _scopes(root):
        for el in scope.children:
            if el.tag == "output":
                for c in list(el.children):
                    if c.tag in _PORTS and c.get("name") == "in" and c.get("type") == "opgraphnode":
                        el.attrs["nodename"] = c.get("value", "")
                        el.children.remove(c)
            if el.tag == "constant":
                _rename_port(el, "color", "value")
            for p in _ports(el) if el.tag not in _PORTS else []:
                if "graphname" in p.attrs:
                    p.attrs["nodegraph"] = p.attrs.pop("graphname")
                if "graphoutput" in p.attrs:
                    p.attrs["output"] = p.attrs.pop("graphoutput")


def _legacy_shaders(root, warnings):
    """<shader shadertype= shadername|shaderprogram=> elements become shader nodes; <material> with a
    <shaderref> to one becomes a surfacematerial, its <override>s set the inputs they publish."""
    shaders = {}
    for el in root.children:
        if el.tag == "shader":
            category = el.get("shaderprogram") or el.get("shadername") or el.get("node")
            if not category:
                continue
            el.tag = category
            el.attrs["type"] = _SHADER_TYPE.get(el.attrs.pop("shadertype", "surface"), "surfaceshader")
            for k in ("shaderprogram", "shadername", "node"):
                el.attrs.pop(k, None)
            shaders[el.get("name")] = el
    for el in root.children:
        if el.tag != "material":
            continue
        refs = [c for c in el.children if c.tag == "shaderref" and c.get("name") in shaders
                and not (c.get("node") or c.get("nodedef"))]
        if not refs:
            continue
        overrides = {c.get("name"): c for c in el.children if c.tag == "override"}
        inputs = []
        for ref in refs:
            shader = shaders[ref.get("name")]
            for p in _ports(shader):
                pub = p.attrs.pop("publicname", None)
                if pub in overrides and "value" in overrides[pub].attrs:
                    p.attrs["value"] = overrides[pub].get("value")
            t = shader.get("type")
            inputs.append(_el("input", {"name": _MATERIAL_INPUT.get(t, "surfaceshader"), "type": t,
                                        "nodename": shader.get("name")}, ref.loc))
        _to_material(el, inputs)


def _to_material(el, inputs):
    volume_only = bool(inputs) and all(i.get("type") == "volumeshader" for i in inputs)
    el.tag = "volumematerial" if volume_only else "surfacematerial"
    el.attrs["type"] = "material"
    el.children = inputs


# ---------------------------------------------------------------- 1.36 -> 1.37

def _v137(root, warnings):
    """Renamed and split nodes of 1.37: invertmatrix, rotate2d/3d, compare -> ifgreatereq,
    transform* by matrix -> transformmatrix, combineN / separateN, geomattrvalue, color2 -> vector2."""
    for scope in _scopes(root):
        for el in scope.children:
            for x in [el] + el.children:
                if x.get("type") == "color2":
                    x.attrs["type"] = "vector2"
            if not _is_node(el):
                continue
            t = el.get("type", "")
            if el.tag == "invert" and t.startswith("matrix"):
                el.tag = "invertmatrix"
            elif el.tag == "rotate":
                el.tag = "rotate3d" if t == "vector3" else "rotate2d"
            elif el.tag == "compare":
                el.tag = "ifgreatereq"
                _rename_port(el, "intest", "value1")
                _rename_port(el, "cutoff", "value2")
                a, b = _port(el, "in1"), _port(el, "in2")
                if a is not None:
                    a.attrs["name"] = "in2"
                if b is not None:
                    b.attrs["name"] = "in1"
            elif el.tag in ("transformpoint", "transformvector", "transformnormal") and _port(el, "mat") is not None:
                el.tag = "transformmatrix"
            elif el.tag == "combine":
                el.tag = "combine%d" % max(2, len(_ports(el)))
            elif el.tag == "separate":
                inp = _port(el, "in")
                el.tag = "separate%d" % _SIZE.get(inp.get("type") if inp is not None else "", 3)
            elif el.tag == "geomattrvalue":
                el.tag = "geompropvalue"
                if "attrname" in el.attrs:
                    el.children.append(_el("input", {"name": "geomprop", "type": "string",
                                                     "value": el.attrs.pop("attrname")}, el.loc))


# ---------------------------------------------------------------- 1.37 -> 1.38

# BSDF nodes renamed in 1.38 (the `base` input they had became a <layer>)
_BSDF_RENAMES = {
    "diffuse_brdf": "oren_nayar_diffuse_bsdf", "burley_diffuse_brdf": "burley_diffuse_bsdf",
    "dielectric_brdf": "dielectric_bsdf", "dielectric_btdf": "dielectric_bsdf",
    "generalized_schlick_brdf": "generalized_schlick_bsdf", "conductor_brdf": "conductor_bsdf",
    "sheen_brdf": "sheen_bsdf", "subsurface_brdf": "subsurface_bsdf", "diffuse_btdf": "translucent_bsdf",
    "thin_film_brdf": "thin_film_bsdf",
}


def _v138(root, warnings):
    _shaderref_materials(root)
    for scope in _scopes(root):
        namer = _Namer(scope)
        for el in list(scope.children):
            if el.tag == "atan2":
                # 1.38 swapped the roles of atan2's inputs
                a, b = _port(el, "in1"), _port(el, "in2")
                if a is not None:
                    a.attrs["name"] = "in2"
                if b is not None:
                    b.attrs["name"] = "in1"
            if el.tag not in _BSDF_RENAMES:
                continue
            old = el.tag
            el.tag = _BSDF_RENAMES[old]
            el.attrs.pop("nodedef", None)
            if old == "dielectric_btdf":
                el.children.append(_el("input", {"name": "scatter_mode", "type": "string", "value": "T"}, el.loc))
            if old == "conductor_brdf":
                _artistic_ior(el, scope, namer)
            base = _port(el, "base")
            if base is not None:
                # a BSDF over a base: a <layer> (named as the node was) of the node over its base
                el.children.remove(base)
                name = el.get("name")
                el.attrs["name"] = namer(name + "__layer_top")
                scope.children.append(_el("layer", {"name": name, "type": "BSDF"}, el.loc, [
                    _el("input", {"name": "top", "type": "BSDF", "nodename": el.get("name")}, el.loc),
                    _el("input", dict(base.attrs, name="base"), base.loc)]))


def _artistic_ior(el, scope, namer):
    """conductor_brdf's reflectivity / edge_color became an artistic_ior node feeding ior / extinction."""
    refl, edge = _port(el, "reflectivity"), _port(el, "edge_color")
    if refl is None and edge is None:
        return
    name = namer(el.get("name") + "__artistic_ior")
    ins = []
    for p in (refl, edge):
        if p is not None:
            el.children.remove(p)
            ins.append(p)
    scope.children.append(_el("artistic_ior", {"name": name, "type": "multioutput"}, el.loc, [
        _el("output", {"name": "ior", "type": "color3"}, el.loc),
        _el("output", {"name": "extinction", "type": "color3"}, el.loc)] + ins))
    for out in ("ior", "extinction"):
        el.children.append(_el("input", {"name": out, "type": "color3", "nodename": name, "output": out}, el.loc))


def _shaderref_materials(root):
    """1.38 replaced <material><shaderref node=...><bindinput/></shaderref></material> by a shader node
    (named as the shaderref) and a surfacematerial (named as the material) that connects it."""
    nodedef_types = {}
    for c in root.children:
        if c.tag == "nodedef":
            outs = [o.get("type") for o in c.children if o.tag == "output"] or [c.get("type")]
            nodedef_types[c.get("name")] = (c.get("node"), outs[0])
            nodedef_types.setdefault("node:" + (c.get("node") or ""), (c.get("node"), outs[0]))
    new_nodes = []
    for el in list(root.children):
        if el.tag != "material":
            continue
        inputs = []
        for ref in [c for c in el.children if c.tag == "shaderref"]:
            nodedef = ref.get("nodedef")
            category, type_name = nodedef_types.get(nodedef) or nodedef_types.get("node:" + (ref.get("node") or ""),
                                                                                 (None, None))
            category = ref.get("node") or category or _category_of(nodedef)
            if not category:
                continue
            type_name = ref.get("type") or type_name or _SHADER_TYPE.get(ref.get("shadertype"), "surfaceshader")
            attrs = {"name": ref.get("name"), "type": type_name}
            if nodedef:
                attrs["nodedef"] = nodedef
            ports = []
            for b in ref.children:
                if b.tag in ("bindinput", "bindparam"):
                    ports.append(_el("input", b.attrs, b.loc))
                elif b.tag == "bindtoken":
                    ports.append(_el("token", b.attrs, b.loc))
            new_nodes.append(_el(category, attrs, ref.loc, ports))
            inputs.append(_el("input", {"name": _MATERIAL_INPUT.get(type_name, "surfaceshader"), "type": type_name,
                                        "nodename": ref.get("name")}, ref.loc))
        if inputs or "type" not in el.attrs:
            _to_material(el, inputs)        # one that binds no shader is an empty surfacematerial
    root.children.extend(new_nodes)


def _category_of(nodedef):
    """ND_standard_surface_surfaceshader -> standard_surface (the library's naming convention)."""
    if not nodedef or not nodedef.startswith("ND_"):
        return None
    stem = nodedef[3:]
    for suffix in ("_surfaceshader", "_volumeshader", "_displacementshader", "_lightshader"):
        if stem.endswith(suffix):
            return stem[: -len(suffix)]
    return stem


# ---------------------------------------------------------------- 1.38 -> 1.39

def _v139(root, warnings):
    _channels_attributes(root)
    _swizzle_nodes(root)
    for scope in _scopes(root):
        namer = _Namer(scope)
        for el in list(scope.children):
            if el.tag == "atan2":
                # 1.39 named atan2's inputs for what they are: in1 is y, in2 is x
                _rename_port(el, "in1", "iny")
                _rename_port(el, "in2", "inx")
            elif el.tag == "normalmap":
                _normalmap(el, scope, namer)
            elif el.tag == "subsurface_bsdf":
                p = _port(el, "radius")
                if p is not None and p.get("type") == "vector3":
                    if _connection(p):
                        conv = namer("convert")
                        scope.children.append(_el("convert", {"name": conv, "type": "color3"}, p.loc, [
                            _el("input", dict(_connection(p), name="in", type="vector3"), p.loc)]))
                        _set_connection(p, {"nodename": conv})
                    p.attrs["type"] = "color3"
        _thin_film_layers(scope, warnings)


def _normalmap(el, scope, namer):
    """1.39 dropped normalmap's `space`: tangent space is the only one; an object-space normal map
    is decoded as normalize(2 * in - 1)."""
    if el.get("nodedef") == "ND_normalmap":
        el.attrs["nodedef"] = "ND_normalmap_float"
    space = _port(el, "space")
    if space is None:
        return
    el.children.remove(space)
    if space.get("value") != "object":
        return
    inp = _port(el, "in")
    source = _connection(inp) if inp is not None and _connection(inp) else {
        "value": inp.get("value") if inp is not None and inp.get("value") else "0.5, 0.5, 1.0"}
    mul, sub = namer("multiply"), namer("subtract")
    loc = el.loc
    scope.children.append(_el("multiply", {"name": mul, "type": "vector3"}, loc, [
        _el("input", dict(source, name="in1", type="vector3"), loc),
        _el("input", {"name": "in2", "type": "float", "value": "2"}, loc)]))
    scope.children.append(_el("subtract", {"name": sub, "type": "vector3"}, loc, [
        _el("input", {"name": "in1", "type": "vector3", "nodename": mul}, loc),
        _el("input", {"name": "in2", "type": "float", "value": "1"}, loc)]))
    el.tag = "normalize"
    el.attrs.pop("nodedef", None)
    el.children = [_el("input", {"name": "in", "type": "vector3", "nodename": sub}, loc)]


_THIN_FILM_BSDFS = ("dielectric_bsdf", "conductor_bsdf", "generalized_schlick_bsdf")


def _thin_film_layers(scope, warnings):
    """1.39 removed thin_film_bsdf: a <layer> of a thin film over a BSDF graph (a single BSDF or a mix, layer
    or sum of them, as 1.38's standard_surface has it) is read as MaterialX 1.39's upgrade reads it: every
    dielectric, conductor or generalized Schlick BSDF upstream of the layer, unless it only transmits
    (scatter_mode "T"), takes the film's thickness and ior (its value or connection) as thinfilm_thickness and
    thinfilm_ior; the layer passes its base on, and the layer and the film are dropped. A film input not set
    is not copied (the 1.39 BSDF keeps its own default: no film)."""
    by_name = {c.get("name"): c for c in scope.children if _is_node(c)}
    for layer in [c for c in scope.children if c.tag == "layer"]:
        top, base = _port(layer, "top"), _port(layer, "base")
        film = by_name.get(top.get("nodename")) if top is not None else None
        under = by_name.get(base.get("nodename")) if base is not None else None
        if film is None or under is None or film.tag != "thin_film_bsdf":
            continue
        filmed = []
        for upstream in _upstream(layer, by_name):
            mode = _port(upstream, "scatter_mode")
            if upstream.tag not in _THIN_FILM_BSDFS or (mode is not None and mode.get("value") == "T"):
                continue
            filmed.append(upstream.get("name"))
            for old, new in (("thickness", "thinfilm_thickness"), ("ior", "thinfilm_ior")):
                p = _port(film, old)
                if p is None:
                    continue
                q = _port(upstream, new)
                if q is not None:       # a film set again (two films over one BSDF): the later one's
                    upstream.children.remove(q)
                upstream.children.append(_el("input", dict(p.attrs, name=new), p.loc))
        if filmed != [under.get("name")]:       # not the one BSDF beneath: what the film is given to is assumed
            warnings.append((layer.loc, "layer '%s': thin_film_bsdf '%s' over %s '%s' (gone in 1.39): its thickness "
                                        "and ior are given to %s, as MaterialX's upgrade gives them"
                             % (layer.get("name"), film.get("name"), under.tag, under.get("name"),
                                "each BSDF beneath that reflects (%s)" % ", ".join(filmed) if filmed
                                else "no BSDF (none beneath takes a film)")))
        name = layer.get("name")
        for el in scope.children:       # the layer's readers read its base
            for p in ([el] if el.tag == "output" else el.children):
                if p.get("nodename") == name and "nodegraph" not in p.attrs:
                    p.attrs["nodename"] = under.get("name")
        scope.children.remove(layer)
        del by_name[name]
        if not any(p.get("nodename") == film.get("name") for el in scope.children for p in [el] + el.children):
            scope.children.remove(film)
            by_name.pop(film.get("name"), None)


def _upstream(node, by_name):
    """The nodes of a scope upstream of `node` (through node connections), each once, `node` itself left out."""
    seen, out, work = {node.get("name")}, [], [node]
    while work:
        el = work.pop()
        for p in _ports(el):
            dep = by_name.get(p.get("nodename")) if "nodename" in p.attrs else None
            if dep is not None and dep.get("name") not in seen:
                seen.add(dep.get("name"))
                out.append(dep)
                work.append(dep)
    return out


# the steps, each applied to documents older than its version
_STEPS = [
    ((1, 26), _legacy_graphs),
    ((1, 26), _legacy_shaders),
    ((1, 37), _v137),
    ((1, 38), _v138),
    ((1, 39), _v139),
]
