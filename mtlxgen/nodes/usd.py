"""UsdPreviewSurface under the seed's rules (UsdPreviewSurface Specification 2.5), where MaterialX's
usd_preview_surface.mtlx departs from it.

The rules are switched by the pipeline option `usd_seed_rules` (CLI `--usd-seed-rules` /
`--no-usd-seed-rules`). Left unset, they are on for documents that come from USD (comes_from_usd): a
document using USD's preview nodes (UsdPreviewSurface, UsdUVTexture, UsdPrimvarReader, UsdTransform2d)
*and* USD's own vocabulary, which MaterialX's usd_preview_surface.mtlx does not know: a `result` output
of a USD node, UsdUVTexture's `sourceColorSpace` input, or the wrap tokens `repeat` / `useMetadata`.
A document written against MaterialX's nodedefs alone (e.g. MaterialX's own Examples/UsdPreviewSurface)
keeps MaterialX's nodegraphs, as its author saw them in MaterialX; pass the option to choose either way.
The rules only touch USD's preview nodes, so other documents never change.

With the rules on (SeedRules, handed to graph building by pipeline.py), graph building resolves these
categories to our own nodedefs in glsl_lib/usd/usd_seed.mtlx instead of MaterialX's (SEED_CATEGORIES),
and accepts the seed's `result` output name for the `out` of USD nodes (UsdPrimvarReader, UsdTransform2d):
- UsdUVTexture: `sourceColorSpace` raw / sRGB / auto (auto: a linear claim in the file's metadata
  means raw; otherwise sRGB when the file is 8-bit with 3 or 4 channels, else raw; OpenImageIO calls
  every PNG sRGB whether or not it says so, so only a linear claim counts as metadata); wrapS / wrapT
  black, clamp, repeat (or periodic), mirror and useMetadata (the file's `wrapS` / `wrapT` string
  metadata, else black); the 1- and 2-channel rules (1: rgb = r, a = 1; 2: rgb = r, a = g; 3: a = 1);
  output = texel * scale + bias; `fallback` when the file cannot be read at generation time.
  Wrapping is done in GLSL (glsl_lib/usd/usd_uvtexture.glsl), so it holds whatever the sampler state;
  the manifest's texture entry also carries the MaterialX address modes, channel count and colour space.
- UsdPrimvarReader: every float, float2, float3 (normal, point, vector), float4 and int reader reads the
  vertex attribute `i_geomprop_VARNAME` where the renderer has bound the geometry's primvar of that name and
  set the reader's flag uniform to 1 (the manifest's "primvars" lists reader, attribute and flag; a varname
  that is no GLSL name part gets a hashed one). Otherwise a float2 reader of any varname reads the renderer's
  texture coordinates (the sphere's, or the stream a stage's mesh binds as its texture coordinates), and the
  others their `fallback`, as the seed says and Storm draws (UsdImaging hands a renderer only the primvars a
  mesh authors, `displayColor` too): on the sphere, which carries no other primvar, always. String and
  filename readers keep MaterialX's graphs.
- UsdPreviewSurface: a nodegraph of ours (usd_seed.mtlx): metallic F0 = F90 = albedo (interpolated
  with the dielectric F0 from ior and F90 = 1), no conductor; opacity is alpha, not refraction;
  opacityThreshold > 0 cuts out (alpha 0 below the threshold, 1 at or above it).
"""
import re

from mtlxgen.base.files import regular_file_problem
from mtlxgen.base.identifiers import sha256

USD_CATEGORIES = ("UsdPreviewSurface", "UsdUVTexture", "UsdPrimvarReader", "UsdTransform2d")

# document category -> the category of our seed-rule nodedefs (glsl_lib/usd/usd_seed.mtlx)
SEED_CATEGORIES = {
    "UsdPreviewSurface": "usd_seed_UsdPreviewSurface",
    "UsdUVTexture": "usd_seed_UsdUVTexture",
    "UsdPrimvarReader": "usd_seed_UsdPrimvarReader",
}

WRAP_MODES = {"black": 0, "clamp": 1, "repeat": 2, "periodic": 2, "mirror": 3}
_MATERIALX_ADDRESS = {"black": "constant", "clamp": "clamp", "repeat": "periodic", "periodic": "periodic",
                      "mirror": "mirror"}
_LINEAR_NAMES = ("linear", "lin_", "scene_linear", "raw", "acescg", "aces2065")


def uses_usd_nodes(doc):
    """True for a document that comes from USD: it uses one of USD's preview nodes anywhere."""
    graphs = [doc.nodes] + [g.nodes for g in doc.nodegraphs.values()]
    return any(n.category in USD_CATEGORIES for nodes in graphs for n in nodes.values())


# what only USD's side of the preview nodes says (MaterialX's usd_preview_surface.mtlx has none of it)
_USD_ONLY_INPUTS = {"UsdUVTexture": ("sourceColorSpace",)}
_USD_ONLY_WRAPS = ("repeat", "useMetadata")


def comes_from_usd(doc):
    """True for a document from USD: a USD stage's (usdstage.py), or one using USD's preview nodes in USD's
    own vocabulary (see above)."""
    if getattr(doc, "usd", None) is not None:
        return True
    graphs = [doc.nodes] + [g.nodes for g in doc.nodegraphs.values()]
    usd_names = set()
    for nodes in graphs:
        usd_names.update(name for name, n in nodes.items() if n.category in USD_CATEGORIES)
    if not usd_names:
        return False
    outputs = [doc.outputs] + [g.outputs for g in doc.nodegraphs.values()]
    ports = [p for nodes in graphs for n in nodes.values() for p in n.inputs.values()]
    ports += [p for outs in outputs for p in outs.values()]
    for p in ports:
        if p.output == "result" and p.nodename in usd_names:
            return True
    for nodes in graphs:
        for n in nodes.values():
            if n.category not in USD_CATEGORIES:
                continue
            if any(name in n.inputs for name in _USD_ONLY_INPUTS.get(n.category, ())):
                return True
            for name in ("wrapS", "wrapT"):
                p = n.inputs.get(name)
                if p is not None and (p.text or p.value) in _USD_ONLY_WRAPS:
                    return True
    return False


def seed_nodedef(node, library):
    """Our seed-rule nodedef for a document node, or None where the rules do not replace it."""
    category = SEED_CATEGORIES.get(node.category)
    if category is None:
        return None
    candidates = library.by_category.get(category) or []
    if len(candidates) > 1 and node.type not in ("multioutput", ""):
        candidates = [nd for nd in candidates if nd.type == node.type]   # none: MaterialX's nodedefs decide
    return candidates[0] if candidates else None


def accepts_result_output(category):
    """The seed names the single output of its primvar and transform nodes `result`."""
    return category.startswith("Usd")


class SeedRules:
    """A target's graph.BuildRules (`base`) with the seed's rules on top: USD's preview nodes resolve to our
    seed-rule nodedefs, and a connection may name the single output of a USD node `result`. Handed to graph
    building by pipeline.py where the rules are on."""

    def __init__(self, base):
        self.base = base

    def nodedef_for(self, node, library):
        return seed_nodedef(node, library) or self.base.nodedef_for(node, library)

    def output_name(self, category, name, outputs):
        if name == "result" and "out" in outputs and accepts_result_output(category):
            return "out"
        return self.base.output_name(category, name, outputs)

    def implements(self, nodedef, library):
        return self.base.implements(nodedef, library)


# ---------------------------------------------------------------- UsdUVTexture

def file_info(path):
    """{channels, bits8, linear_claim, wrapS, wrapT} of an image file from its header, or None."""
    if not path or regular_file_problem(path) is not None:     # no devices, FIFOs or /proc (files.py)
        return None
    from mtlxgen.base.images import _oiio_errors, captured_stderr
    try:
        import OpenImageIO as oiio
        with captured_stderr():
            inp = oiio.ImageInput.open(path)
            if inp is None:
                _oiio_errors()          # taken: a pending error is printed on several lines at exit
                return None
            try:
                spec = inp.spec()
                attrs = {a.name: a.value for a in spec.extra_attribs}
                fmt = str(spec.format)
            finally:
                inp.close()
                _oiio_errors(inp)
    except Exception:
        return None
    cs = str(attrs.get("oiio:ColorSpace", "")).lower()
    gamma = attrs.get("oiio:Gamma")
    linear = any(cs.startswith(p) for p in _LINEAR_NAMES) or (
        isinstance(gamma, (int, float)) and abs(float(gamma) - 1.0) < 1e-3)
    return {"channels": int(spec.nchannels), "bits8": fmt in ("uint8", "int8"), "linear_claim": linear,
            "wrapS": str(attrs.get("wrapS", "")), "wrapT": str(attrs.get("wrapT", ""))}


def _wrap(node, em, name, info):
    value = node.static.get(name) or "useMetadata"
    if value == "useMetadata":
        value = (info or {}).get(name) or "black"
        if value not in WRAP_MODES:
            value = "black"
    if value not in WRAP_MODES:
        em.fail(node, "%s '%s' is not one of black, clamp, repeat, mirror, useMetadata" % (name, value))
    return value


def source_is_srgb(source, info):
    """The seed's sourceColorSpace rule: does the file read through the sRGB transfer curve?"""
    if source == "sRGB":
        return True
    if source == "raw" or info is None:
        return False
    if info["linear_claim"]:
        return False
    return info["bits8"] and info["channels"] in (3, 4)


def uv_texture(node, em):
    """UsdUVTexture by the seed's rules. A file naming <UDIM> (or <UVTILE>) reads one sampler per tile on
    disk: the tile under st, at st less the tile's corner; st on no tile reads the fallback."""
    from mtlxgen.base.resolve import resolve_file
    from mtlxgen.nodes.handlers import _TILE_TOKENS, _default_value, _texture_file, _udim_tiles
    sampler, value, _ = _texture_file(node, em)
    tiles = _udim_tiles(node, em, sampler, value, None) if _TILE_TOKENS.search(value) else None
    if tiles:
        info = file_info(str(em.uniform(tiles[min(tiles)]).value))   # the first tile speaks for all
    else:
        info = file_info(resolve_file(value, em.graph.doc_path)) if tiles is None else None
    wrap_s, wrap_t = _wrap(node, em, "wrapS", info), _wrap(node, em, "wrapT", info)
    source = node.static.get("sourceColorSpace") or "auto"
    if source not in ("raw", "sRGB", "auto"):
        em.fail(node, "sourceColorSpace '%s' is not one of raw, sRGB, auto" % source)
    srgb = source_is_srgb(source, info)
    channels = info["channels"] if info else 4
    sampling = {
        "uaddressmode": _MATERIALX_ADDRESS[wrap_s], "vaddressmode": _MATERIALX_ADDRESS[wrap_t],
        "filtertype": "linear", "default": _default_value(node, "fallback"),
        "colorspace": "srgb_texture" if srgb else "raw", "channels": channels,
        "usd_wrap": [wrap_s, wrap_t], "usd_source_colorspace": source,
    }
    texel = em.fresh(node.id + "_texel")
    fallback = em.input_expr(node, "fallback")
    if info is None:            # the file cannot be read: the seed's fallback
        em.textures[sampler] = sampling
        expr = fallback
    else:
        em.require("usd/usd_uvtexture.glsl")
        args = (WRAP_MODES[wrap_s], WRAP_MODES[wrap_t], channels, "true" if srgb else "false",
                em.input_expr(node, "scale"), em.input_expr(node, "bias"))
        if tiles:
            st, cell = em.fresh(node.id + "_st"), em.fresh(node.id + "_tile")
            em.line("vec2 %s = %s;" % (st, em.input_expr(node, "st")))
            em.line("ivec2 %s = ivec2(floor(%s));" % (cell, st))
            expr = fallback
            for (cu, cv), tile in sorted(tiles.items(), reverse=True):
                em.textures[tile] = dict(sampling)
                expr = "(%s == ivec2(%d, %d) ? mg_usd_uvtexture(%s, %s - vec2(%d.0, %d.0), %d, %d, %d, %s, %s, %s) : %s)" % (
                    (cell, cu, cv, tile, st, cu, cv) + args + (expr,))
            em.drop_unread_uniform(sampler, node)     # the <UDIM> pattern itself is no file
        else:
            em.textures[sampler] = sampling
            expr = "mg_usd_uvtexture(%s, %s, %d, %d, %d, %s, %s, %s)" % ((sampler, em.input_expr(node, "st")) + args)
    em.line("vec4 %s = %s;" % (texel, expr))
    return {"r": texel + ".r", "g": texel + ".g", "b": texel + ".b", "a": texel + ".a", "rgb": texel + ".rgb",
            "rgba": texel}


# ---------------------------------------------------------------- UsdPrimvarReader

_ATTRIBUTE_PART = re.compile(r"[A-Za-z0-9]+(_[A-Za-z0-9]+)*", re.ASCII)   # what streams.py takes after geomprop_
MAX_ATTRIBUTE_PART = 40


def primvar_attribute(varname):
    """The vertex attribute carrying primvar `varname`: i_geomprop_VARNAME, as MaterialX's geompropvalue names
    it; a name that cannot be part of a GLSL identifier (`a:b`, `x__y`, too long) keeps its letters and digits
    and gains a hash of the whole name."""
    if _ATTRIBUTE_PART.fullmatch(varname) and len(varname) <= MAX_ATTRIBUTE_PART:
        return "i_geomprop_" + varname
    kept = "_".join(re.findall(r"[A-Za-z0-9]+", varname, re.ASCII))[:24] or "primvar"
    digest = sha256(varname.encode("utf-8", "surrogateescape")).hexdigest()[:10]
    return "i_geomprop_%s_%s" % (kept, digest)


def primvar_reader(node, em):
    """UsdPrimvarReader_float/float2/float3/float4/int: the primvar's vertex attribute where the renderer binds
    one (flag uniform 1), else the renderer's texture coordinates (float2) or the fallback (the others). In the
    vertex stage (displacement) there is no flag: the texture coordinates or the fallback."""
    out_type = node.outputs["out"]
    otherwise = em.stream("texcoord_0") if out_type == "vector2" else em.input_expr(node, "fallback")
    varname = node.static.get("varname") or ""
    if not varname or em.stage == "vertex":
        return {"out": otherwise}
    attribute = primvar_attribute(varname)
    taken = em.streams.get(attribute[len("i_"):])
    if taken is not None and taken.type != em.glsl_type(out_type):     # the same primvar read as another type
        attribute = "%s_%s" % (attribute, out_type)
    value = em.stream(attribute[len("i_"):], out_type)
    flag = em.add_uniform(node.id + "_primvar", "integer", 0, node.loc)
    em.primvars.append({"varname": varname, "attribute": attribute, "type": em.glsl_type(out_type),
                        "uniform": flag})
    return {"out": "(%s != 0 ? %s : %s)" % (flag, value, otherwise)}


NODES = {
    "usd_seed_UsdUVTexture": {"handler": uv_texture},
}

NODEDEFS = {"ND_usd_seed_UsdPrimvarReader_%s" % t: {"handler": primvar_reader}
            for t in ("float", "vector2", "vector3", "vector4", "integer")}
