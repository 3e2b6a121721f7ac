"""USD stages as input: the materials of a .usd / .usda / .usdc / .usdz stage as one MaterialX Document.

The stage is opened and composed by Pixar's own library (`usd-core`, module `pxr`): references,
payloads, sublayers and variants (`--variant SET=NAME`, authored in the session layer) are USD's
business; this module reads the composed result. USD opens every layer it composes itself, so before it
composes anything each one is found from the layer naming it (sublayers, references and payloads in
variants too, paths given by variable expressions, value clips and clip templates), its file checked to be
a regular file within the USD size cap (a FIFO would block USD forever), and opened one at a time; the
stage is then composed from those opened layers (checked_layers). Every UsdShadeMaterial becomes a `surfacematerial`
element named by its prim path (`/Root/Looks/Wood` -> `Root_Looks_Wood`), and its network becomes
the same dataclasses document.py builds from XML, so everything after the document (graph, emit,
render) is shared with .mtlx input:

- Shader prims become nodes. `info:id` UsdPreviewSurface, UsdUVTexture, UsdPrimvarReader_* and
  UsdTransform2d are USD's preview nodes, resolved by the UsdPreviewSurface seed's rules (nodes/usd.py;
  on for stages unless --no-usd-seed-rules); an id naming a MaterialX nodedef (`ND_*`) becomes a node
  of that nodedef. Inputs USD's preview nodes do not define (`specular`, the old `isSRGB`) are ignored,
  as USD's shader registry ignores them, and listed by `info`.
- NodeGraph prims become nodegraphs, their inputs the nodegraph's interface; a Material's own inputs
  become document inputs (`ELEMENT_input`, public uniforms) that its shaders read by interfacename.
  Connections that cross a NodeGraph's boundary other than through its ports (legal in USD, not in
  MaterialX) get a port of their own; connections between 3-float (or 4-float) types USD treats as
  one (float3, color3f, vector3f, normal3f) get a `convert` node.
- Asset inputs are resolved by USD's asset resolution, relative to the layer that authored them;
  textures inside a .usdz package are copied out once to the cache (MTLXGEN_CACHE, else
  ~/.cache/mtlxgen) because the renderer reads image files by path. `<UDIM>` patterns are anchored to
  the authoring layer, their tiles found on disk (or in the package). A file that cannot be found is a
  problem naming the layer, prim and attribute, and the fallback drawn in its place; the element is
  still written.
- A prim referencing a .mtlx document (USD's MaterialX file-format plugin, absent from usd-core) has its
  materials read from that file by our own reader and placed where the plugin would put them: a
  reference to </MaterialX> (or the default prim) puts material M at PRIM/Materials/M, one to
  </MaterialX/Materials> at PRIM/M, one to </MaterialX/Materials/M> at PRIM.
- A material with both `outputs:mtlx:surface` and `outputs:surface` draws the one `render_context`
  names ("mtlx", the default, as Storm with MaterialX does, or "universal"); a material with only one
  draws that one. The manifest's "usd" entry records the prim, the context drawn and, for materials
  read from a .mtlx file, that file.

USD has no line numbers: problems name `FILE:PRIM_PATH.ATTRIBUTE` (diagnostics.Loc's `where`), FILE
being the layer holding the strongest opinion.
"""
import hashlib
import os
import re
from mtlxgen.base.records import dataclass, field

from mtlxgen.base import mxtypes
from mtlxgen.base.diagnostics import Loc, MtlxError
from mtlxgen.read.document import Document, Node, NodeGraph, Port
from mtlxgen.base.files import check_regular, quoted, regular_file_problem

USD_EXTENSIONS = (".usd", ".usda", ".usdc", ".usdz")
RENDER_CONTEXTS = ("mtlx", "universal")
MAX_CHAIN = 64                  # interface inputs passing a connection on, followed at most this deep
MAX_PACKAGED_BYTES = 2 ** 28    # a texture copied out of a .usdz package


def is_usd(path):
    return os.path.splitext(str(path))[1].lower() in USD_EXTENSIONS


# Outputs that the registry (Sdr) definitions of UsdShade's own shaders declare (UsdPreviewSurface Specification
# 2.5), beyond the MaterialX nodedef that stands for them here: a connection to one of them is resolved even where
# the shader prim does not author it.
_SDR_OUTPUTS = {"UsdPreviewSurface": ("surface", "displacement"), "UsdUVTexture": ("r", "g", "b", "a", "rgb"),
                "UsdTransform2d": ("result",)}


def _declared_outputs(spec):
    """The output names a shader's definition declares: its nodedef's, and for UsdShade's own shaders the Sdr
    definition's (the registry itself where USD has it)."""
    names = set(spec.outputs) | set(_SDR_OUTPUTS.get(spec.shader_id, ()))
    if spec.shader_id.startswith("UsdPrimvarReader_"):
        names.add("result")
    if not names and spec.shader_id:
        try:
            from pxr import Sdr
            node = Sdr.Registry().GetShaderNodeByIdentifier(spec.shader_id)
            names.update(node.GetShaderOutputNames() if node else ())
        except Exception:           # no Sdr in this USD build, or a plugin that fails: the nodedef's alone
            pass
    return names


@dataclass(frozen=True)
class StageOptions:
    variants: tuple = ()            # ((variant set, variant name), ...) selected before reading
    render_context: str = "mtlx"    # which surface a material with both draws


@dataclass
class MaterialInfo:
    element: str
    prim: str                       # prim path of the UsdShadeMaterial
    loc: Loc
    context: str = None             # "mtlx" or "universal": the surface output drawn
    contexts: tuple = ()            # the surface outputs the material has
    source: str = None              # the .mtlx document a material read from a referenced file comes from
    shaders: list = field(default_factory=list)     # [(prim path or node name, shader id)]
    problems: list = field(default_factory=list)    # [(Loc, message)]: the element cannot be built
    notes: list = field(default_factory=list)       # [(Loc, message)]: reported, the element still drawn
    ignored: list = field(default_factory=list)     # [(Loc, message)]: listed by info only
    primvars: list = field(default_factory=list)    # varnames of its float2 primvar readers (the stage's meshes)
    vertex_primvars: list = field(default_factory=list)     # primvars its readers and geompropvalues read


@dataclass
class StageInfo:
    path: str
    options: StageOptions
    materials: dict = field(default_factory=dict)   # element -> MaterialInfo, in stage order
    by_prim: dict = field(default_factory=dict)     # prim path -> element
    problems: list = field(default_factory=list)    # [(Loc, message)] of the stage as a whole

    def element_for(self, name):
        """An element name, or a material's prim path, as the element name (MtlxError for neither)."""
        if name in self.materials:
            return name
        if name in self.by_prim:
            return self.by_prim[name]
        if name.startswith("/"):
            raise MtlxError((Loc(self.path, where=name), "no UsdShadeMaterial at this prim path"))
        raise MtlxError((Loc(self.path, 0), "no material '%s' on the stage (materials are named by prim path: "
                                            "/Root/Looks/Wood or Root_Looks_Wood)" % name))

    def manifest(self, name):
        m = self.materials[name]
        entry = {"prim": m.prim, "render_context": m.context}
        if m.source:
            entry["mtlx_document"] = m.source
        return entry


@dataclass
class StageDocument(Document):
    """A Document read from a USD stage (`usd` says where each element came from)."""
    usd: StageInfo = None


def load(path, library_dirs=(), options=None):
    """The materials of the USD stage at `path` as a StageDocument. Raises MtlxError where the stage
    cannot be opened or holds no material; problems of single materials are kept with them
    (StageInfo.materials[element].problems) so that the others are still drawn."""
    options = options or StageOptions()
    if options.render_context not in RENDER_CONTEXTS:
        raise MtlxError((Loc(path, 0), "render context '%s' is not one of %s"
                         % (options.render_context, ", ".join(RENDER_CONTEXTS))))
    try:
        from pxr import Usd  # noqa: F401
    except ImportError:
        raise MtlxError((Loc(path, 0), "reading USD stages needs Pixar's usd-core (pip install usd-core)")) from None
    from mtlxgen.read.library import load_library
    library = load_library(tuple(library_dirs))
    with _quiet_stderr():
        stage, layers = _open(path)
        reader = _StageReader(stage, path, library, library_dirs, options)
        reader.read()
        del layers          # held until the variant selections and asset reads are done
    doc = reader.doc
    if not doc.usd.materials:
        problems = doc.usd.problems + [(Loc(path, 0), "nothing to render: no UsdShadeMaterial on the stage")]
        raise MtlxError(problems)
    return doc


def scene_files(paths):
    """Of USD files found in a directory, those to draw as stages of their own (batch and golden sweeps): the
    ones no other of them composes (a sublayer, reference or payload is drawn as part of the stage using it,
    as its default variants select it) that hold a UsdShadeMaterial or reference a .mtlx document. A file USD
    cannot open is kept: drawing it says why. Without usd-core every file is kept (each then says so)."""
    paths = list(paths)
    try:
        from pxr import Usd  # noqa: F401
    except ImportError:
        return paths
    used, keep = set(), {}
    with _quiet_stderr():
        for p in paths:
            try:
                stage, _ = _open(p)     # every layer checked first: a FIFO among them is refused, not waited on
            except MtlxError:           # unparsable, or not a regular file: drawing it says why
                keep[p] = True
                continue
            own = os.path.realpath(p)
            for layer in stage.GetUsedLayers():
                real = layer.realPath
                if real and not layer.anonymous and os.path.realpath(real) != own:
                    used.add(os.path.realpath(real))
            keep[p] = _has_materials(stage)
    return [p for p in paths if keep[p] and os.path.realpath(p) not in used]


def _has_materials(stage):
    from pxr import Usd, UsdShade
    for prim in stage.Traverse(Usd.TraverseInstanceProxies()):
        if prim.IsA(UsdShade.Material):
            return True
        for spec in prim.GetPrimStack():
            items = list(spec.referenceList.GetAddedOrExplicitItems()) if spec.hasReferences else []
            items += list(spec.payloadList.GetAddedOrExplicitItems()) if spec.hasPayloads else []
            if any((item.assetPath or "").lower().endswith(".mtlx") for item in items):
                return True
    return False


# ---------------------------------------------------------------- opening

def _quiet_stderr():
    """USD reports warnings by writing to the process's stderr; problems are reported here instead, one
    line each, so its writes during reading go to a scratch file (images.captured_stderr, imported on use)."""
    from mtlxgen.base.images import captured_stderr
    return captured_stderr()


def _tf_message(e):
    """The first message of a Tf.ErrorException ("'file:3:3: Expected }'" out of USD's report)."""
    found = []
    for chunk in re.split(r"\n\s*Error in ", str(e)):
        head, sep, rest = chunk.partition(" : '")
        if sep and rest.rstrip().endswith("'"):
            found.append(rest.rstrip()[:-1])
    text = found[0] if found else (str(e).strip().splitlines() or [type(e).__name__])[-1]
    return " ".join(text.split())


MAX_LAYERS = 10000              # layers one stage composes (sublayers, references, payloads, value clips)
MAX_TEMPLATE_CLIPS = 10000      # value clips a clip template may name


def _open(path):
    """(stage, layers): the composed stage of the USD file at `path`, and the layers it composes, opened one at a
    time after their files were checked (held: the stage's later composition finds them in USD's registry)."""
    from pxr import Usd
    layers = checked_layers(path)
    try:
        stage = Usd.Stage.Open(layers[0], Usd.Stage.LoadAll)
    except Exception as e:   # Tf.ErrorException: unparsable layer, unknown format
        raise MtlxError((Loc(path, 0), "cannot open the USD stage: %s" % _tf_message(e))) from None
    if stage is None:
        raise MtlxError((Loc(path, 0), "cannot open the USD stage"))
    return stage, layers


def _layer_name(layer, path):
    """A layer as problem lines name it: `path` for the root layer, else its path relative to here."""
    real = layer.realPath or ""
    if real and os.path.realpath(real) == os.path.realpath(path):
        return path
    if real:
        rel = os.path.relpath(real)
        return real if rel.startswith("..") else rel
    return layer.identifier


def checked_layers(path):
    """The layers the stage at `path` composes, root first, each opened only after its file was found to be a
    regular file within the USD size cap (files.py): USD opens every sublayer, reference, payload and value clip
    itself, and a FIFO among them would block it forever, a device never end. The dependencies are read from each
    parsed layer (variable expressions evaluated as composition evaluates them: a referenced layer stack takes its
    root layer's variables, overridden by the referencing stack's) and checked before they are opened. Raises
    MtlxError, one line at the layer that names the file, for a file that is not one; files that are missing or do
    not parse are left for composition to report."""
    from pxr import Ar, Sdf
    root = os.path.abspath(path)
    check_regular(root, Loc(path, 0), "USD stage", "usd")
    from mtlxgen.base.images import _utf8       # USD takes paths as UTF-8 text, as OpenImageIO does
    if not _utf8(root):
        raise MtlxError((Loc(path, 0), "USD cannot open a file whose path is not UTF-8 text (rename it)"))
    resolver = Ar.GetResolver()
    with Ar.ResolverContextBinder(resolver.CreateDefaultContextForAsset(root)):
        try:
            layer = Sdf.Layer.FindOrOpen(root)
        except Exception as e:   # Tf.ErrorException: unparsable layer, unknown format
            raise MtlxError((Loc(path, 0), "cannot open the USD stage: %s" % _tf_message(e))) from None
        if layer is None:
            raise MtlxError((Loc(path, 0), "cannot open the USD stage"))
        layers, seen = [layer], set()
        queue = [(layer, dict(layer.expressionVariables or {}))]
        while queue:
            layer, variables = queue.pop(0)
            key = (layer.identifier, repr(sorted(variables.items())))
            if key in seen:
                continue
            seen.add(key)
            sublayers = set(layer.subLayerPaths)
            for asset in layer.GetCompositionAssetDependencies():
                child = _checked_dependency(layer, asset, variables, path, resolver)
                if child is None:
                    continue
                if child not in layers:
                    layers.append(child)
                # a sublayer is of this layer stack (its variables); a reference or payload starts a stack of its
                # own (the referenced layer's variables, overridden by these); a path used both ways goes both ways
                own = dict(child.expressionVariables or {})
                if asset in sublayers:
                    queue.append((child, variables))
                if asset not in sublayers or (own and _used_as_reference(layer, asset)):
                    queue.append((child, dict(own, **variables)))
            for clip in _clip_layers(layer, path, resolver):
                if clip not in layers:
                    layers.append(clip)
            if len(layers) > MAX_LAYERS:
                raise MtlxError((Loc(path, 0), "the stage composes more than %d layers" % MAX_LAYERS))
    return layers


def _used_as_reference(layer, asset):
    """Whether a prim spec of `layer` references or payloads `asset` (only asked of a sublayer's path)."""
    return _dependency_site(layer, asset, sublayers=False) is not None


def _dependency_site(layer, asset, sublayers=True):
    """(what, prim path or None) of the first place `layer` names `asset`: a sublayer, a reference or payload of a
    prim (in a variant too); None where it does not."""
    if sublayers and asset in layer.subLayerPaths:
        return "sublayer", None
    found = []

    def visit(spec):
        for what, listed in (("reference", spec.referenceList), ("payload", spec.payloadList)):
            if any(item.assetPath == asset for item in listed.GetAddedOrExplicitItems()) \
                    or any(item.assetPath == asset for item in listed.prependedItems) \
                    or any(item.assetPath == asset for item in listed.appendedItems):
                found.append((what, str(spec.path)))
                return True
        for vset in spec.variantSets.values():
            for variant in vset.variants.values():
                if visit(variant.primSpec):
                    return True
        return any(visit(child) for child in spec.nameChildren.values())

    for spec in layer.rootPrims.values():
        if visit(spec):
            break
    return found[0] if found else None


def _resolved_file(layer, asset, resolver):
    """(identifier, resolved path, the file to check) of an asset path a layer names, or None where it resolves
    to nothing (missing: composition reports it)."""
    from pxr import Sdf
    identifier = layer.ComputeAbsolutePath(asset)
    file_path, _ = Sdf.Layer.SplitIdentifier(identifier)
    resolved = str(resolver.Resolve(file_path) or "")
    if not resolved:
        return None
    outer = _split_package(resolved)[0] if resolved.endswith("]") and "[" in resolved else resolved
    return identifier, resolved, outer


def _checked_dependency(layer, asset, variables, path, resolver):
    """The layer a sublayer, reference or payload path names, opened after its file was checked; None where it
    names nothing to open (missing, a .mtlx document: read_mtlx_reference's, an expression that does not
    evaluate, a file USD cannot parse: composition reports those)."""
    from pxr import Sdf
    authored = asset
    if asset.startswith("`"):
        result = Sdf.VariableExpression(asset).Evaluate(variables)
        if result.errors or not isinstance(result.value, str) or not result.value:
            return None
        asset = result.value
    if Sdf.Layer.IsAnonymousLayerIdentifier(asset):
        return None
    if asset.lower().endswith(".mtlx"):
        return None
    found = _resolved_file(layer, asset, resolver)
    if found is None:
        return None
    identifier, resolved, outer = found
    why = regular_file_problem(outer, "usd")
    if why is not None:
        what, prim = _dependency_site(layer, authored) or ("dependency", None)
        shown = quoted(authored) + ("" if resolved == asset else " (%s)" % resolved)
        raise MtlxError((Loc(_layer_name(layer, path), 0, prim), "%s %s is %s" % (what, shown, why)))
    try:
        return Sdf.Layer.FindOrOpen(identifier)
    except Exception:       # unparsable: composition reports it
        return None


def _clip_layers(layer, path, resolver):
    """The value clip layers (and clip manifests) `layer`'s prims name, checked and opened: USD opens them itself
    when the stage is composed."""
    from pxr import Sdf
    out = []
    for prim, clips in _clip_sets(layer):
        loc = Loc(_layer_name(layer, path), 0, prim)
        for name, clip_set in clips.items():
            assets = [getattr(a, "path", str(a)) for a in clip_set.get("assetPaths", ()) or ()]
            manifest = clip_set.get("manifestAssetPath")
            if manifest is not None and getattr(manifest, "path", str(manifest)):
                assets.append(getattr(manifest, "path", str(manifest)))
            template = clip_set.get("templateAssetPath")
            if template:
                assets += _template_clips(layer, str(template), clip_set, loc, name)
            for asset in assets:
                found = _resolved_file(layer, asset, resolver)
                if found is None:
                    continue
                identifier, resolved, outer = found
                why = regular_file_problem(outer, "usd")
                if why is not None:
                    raise MtlxError((loc, "value clip %s of clip set '%s' is %s" % (quoted(asset), name, why)))
                try:
                    clip = Sdf.Layer.FindOrOpen(identifier)
                except Exception:
                    clip = None
                if clip is not None:
                    out.append(clip)
    return out


def _clip_sets(layer):
    """(prim path, {clip set: its dictionary}) for the prims of `layer` (variants too) that author `clips`."""
    prims, out = [], []
    layer.Traverse(layer.pseudoRoot.path,
                   lambda p: prims.append(p) if p.IsPrimPath() or p.IsPrimVariantSelectionPath() else None)
    for p in prims:
        spec = layer.GetPrimAtPath(p)
        if spec is not None and spec.HasInfo("clips"):
            clips = spec.GetInfo("clips")
            if clips:
                out.append((str(p), dict(clips)))
    return out


def _template_clips(layer, template, clip_set, loc, name):
    """The files a clip template could name (those on disk matching its pattern), after its clip count is checked:
    a template of a billion clips would keep USD busy generating their paths."""
    try:
        start, end = float(clip_set.get("templateStartTime")), float(clip_set.get("templateEndTime"))
        stride = float(clip_set.get("templateStride"))
    except (TypeError, ValueError):
        return []
    if stride > 0 and end >= start and (end - start) / stride + 1 > MAX_TEMPLATE_CLIPS:
        raise MtlxError((loc, "clip set '%s': its template names %d value clips, more than %d"
                         % (name, int((end - start) / stride + 1), MAX_TEMPLATE_CLIPS)))
    full = layer.ComputeAbsolutePath(template)
    if full.endswith("]"):
        return []           # inside a package: no FIFO can be there
    folder, base = os.path.split(full)
    pattern = re.compile(re.sub(r"(\\#)+", r"\\d+", re.escape(base)) + r"\Z")
    try:
        names = os.listdir(folder or ".")
    except OSError:
        return []
    return [os.path.join(folder, n) for n in names if pattern.match(n)]


def select_variants(stage, path, variants):
    """Author each SET=NAME selection in the session layer on every prim with a variant set SET (again
    where a selection reveals prims with more). [(Loc, problem)] for sets or names that do not exist."""
    from pxr import Usd
    problems = []
    with Usd.EditContext(stage, stage.GetSessionLayer()):
        for set_name, variant in variants:
            seen_set, applied = False, set()
            for _ in range(MAX_CHAIN):
                pending = []
                for prim in stage.Traverse(Usd.PrimAllPrimsPredicate):
                    vsets = prim.GetVariantSets()
                    if not vsets.HasVariantSet(set_name):
                        continue
                    seen_set = True
                    vset = vsets.GetVariantSet(set_name)
                    names = vset.GetVariantNames()
                    key = str(prim.GetPath())
                    if variant not in names:
                        if key not in applied:
                            applied.add(key)
                            problems.append((Loc(path, where=key), "variant set '%s' has no variant '%s' (variants: %s)"
                                             % (set_name, variant, ", ".join(names) or "none")))
                        continue
                    if vset.GetVariantSelection() != variant:
                        pending.append(vset)
                if not pending:
                    break
                for vset in pending:
                    vset.SetVariantSelection(variant)
            if not seen_set:
                problems.append((Loc(path, 0), "no variant set '%s' on the stage%s" % (set_name, _sets_hint(stage))))
    return problems


def _sets_hint(stage):
    from pxr import Usd
    names = sorted({n for p in stage.Traverse(Usd.PrimAllPrimsPredicate) for n in p.GetVariantSets().GetNames()})
    return " (variant sets: %s)" % ", ".join(names) if names else " (it has none)"


# ---------------------------------------------------------------- types and values

# USD value type names -> MaterialX types (role-less 3-float types are vectors until a consumer says colour)
_SDF_TYPES = {
    "float": "float", "double": "float", "half": "float", "int": "integer", "uchar": "integer", "uint": "integer",
    "bool": "boolean", "string": "string", "token": "string", "asset": "filename",
    "float2": "vector2", "double2": "vector2", "half2": "vector2", "texCoord2f": "vector2", "texCoord2d": "vector2",
    "texCoord2h": "vector2",
    "float3": "vector3", "double3": "vector3", "half3": "vector3", "vector3f": "vector3", "vector3d": "vector3",
    "vector3h": "vector3", "normal3f": "vector3", "normal3d": "vector3", "normal3h": "vector3", "point3f": "vector3",
    "point3d": "vector3", "point3h": "vector3", "texCoord3f": "vector3", "texCoord3d": "vector3",
    "color3f": "color3", "color3d": "color3", "color3h": "color3",
    "float4": "vector4", "double4": "vector4", "half4": "vector4", "color4f": "color4", "color4d": "color4",
    "color4h": "color4", "quatf": "vector4", "quatd": "vector4", "quath": "vector4",
    "matrix3d": "matrix33", "matrix4d": "matrix44",
}

# types USD connects freely (one Sdf value type underneath); a consumer of the other reads through `convert`
_SAME_SIZE = {"vector3": "color3", "color3": "vector3", "vector4": "color4", "color4": "vector4"}

_PRIMVAR_TYPES = {"float": "float", "float2": "vector2", "float3": "vector3", "float4": "vector4", "int": "integer",
                  "string": "string", "normal": "vector3", "point": "vector3", "vector": "vector3",
                  "matrix": "matrix44"}

# primvar readers drawn from a vertex attribute on the stage's meshes (float2 ones also choose the texture coordinates)
_VERTEX_READERS = tuple("UsdPrimvarReader_" + t for t in ("float", "float2", "float3", "float4", "int", "normal",
                                                          "point", "vector"))

USD_SHADER_IDS = ("UsdPreviewSurface", "UsdUVTexture", "UsdPrimvarReader_<type>", "UsdTransform2d")


def mx_type_of(sdf_type):
    return _SDF_TYPES.get(str(sdf_type))


def _components(value):
    if type(value).__module__.startswith("pxr.Vt"):     # arrays (float[], color3f[]): no MaterialX input holds one
        raise TypeError(type(value).__name__)
    try:
        return [float(x) for x in value]
    except (TypeError, ValueError):
        pass
    if hasattr(value, "GetRow"):        # Gf.Matrix3d / Matrix4d: row by row, as MaterialX writes them
        n = value.dimension[0]
        return [float(value[i][j]) for i in range(n) for j in range(n)]
    if hasattr(value, "GetReal"):       # quaternions
        return [float(x) for x in value.GetImaginary()] + [float(value.GetReal())]
    raise TypeError(type(value).__name__)


def value_text(value, mx_type):
    """A USD value as the MaterialX value string of `mx_type` (ValueError_ where it does not fit)."""
    if mx_type in ("string", "filename"):
        return str(getattr(value, "path", value))
    if type(value).__module__.startswith("pxr.Vt"):
        raise mxtypes.ValueError_("an array (%s) for a %s input" % (type(value).__name__, mx_type))
    if mx_type == "boolean":
        if isinstance(value, (bool, int)):
            return "true" if value else "false"
        raise mxtypes.ValueError_("a %s value for a boolean input" % type(value).__name__)
    if mx_type == "integer":
        if isinstance(value, bool) or isinstance(value, int) or (isinstance(value, float) and value.is_integer()):
            return str(int(value))
        raise mxtypes.ValueError_("%r is not a whole number" % (value,))
    if mx_type == "float":
        if isinstance(value, (bool, int, float)):
            return repr(float(value))
        raise mxtypes.ValueError_("a %s value for a float input" % type(value).__name__)
    size = mxtypes.components(mx_type)
    if size > 1:
        try:
            parts = _components(value)
        except TypeError:
            raise mxtypes.ValueError_("a %s value for a %s input" % (type(value).__name__, mx_type)) from None
        if len(parts) != size:
            raise mxtypes.ValueError_("%d numbers for a %s input, which takes %d" % (len(parts), mx_type, size))
        return ", ".join(repr(x) for x in parts)
    raise mxtypes.ValueError_("USD values of type %s cannot be read" % mx_type)


def element_name(prim_path):
    """/Root/Looks/Wood -> Root_Looks_Wood (variant selections in a path, if any, dropped)."""
    text = re.sub(r"\{[^}]*\}", "/", str(prim_path)).strip("/")
    return re.sub(r"/+", "_", text) or "root"


# ---------------------------------------------------------------- the reader

@dataclass
class _Spec:
    """What a shader prim is: the node it becomes and the types of its ports."""
    category: str
    type: str
    nodedef: str                # the node's `nodedef=` (None: resolved by category, as USD's ids are)
    inputs: dict                # input name -> MaterialX type (the inputs the node takes)
    outputs: dict               # output name -> MaterialX type
    shader_id: str
    usd_preview: bool           # USD's preview nodes: inputs they do not define are ignored
    problem: str = None         # why the prim cannot be a node
    decl: object = None         # the NodeDef its port types (and defaults) come from


class _Scope:
    """Where a converted node lives: the document (graph None) or one NodeGraph prim's nodegraph."""

    def __init__(self, path, graph):
        self.path = path            # NodeGraph prim path, or None for the document
        self.graph = graph          # document.NodeGraph or None
        self.taken = set()


class _StageReader:
    def __init__(self, stage, path, library, library_dirs, options):
        self.stage = stage
        self.path = path
        self.lib = library
        self.library_dirs = tuple(library_dirs)
        self.options = options
        self.doc = StageDocument(path=path, version="1.39", colorspace="lin_rec709",
                                 usd=StageInfo(path=path, options=options))
        self.taken = set()                  # top-level names: nodes, nodegraphs, document inputs
        self.scopes = {None: _Scope(None, None)}
        self.names = {}                     # (scope path, prim path) -> node name in that scope
        self.items = {}                     # item key -> (problems, notes, ignored, deps, shaders)
        self.specs = {}
        self.synth = {}                     # (scope path, source key) -> port name in that scope
        self.cache_dir = None
        self.image_problems = {}            # texture file -> why it cannot be bound, or None

    # ---------- names and locations ----------
    def layer_name(self, layer):
        return _layer_name(layer, self.path)

    def prim_loc(self, prim):
        stack = prim.GetPrimStack()
        return Loc(self.layer_name(stack[0].layer) if stack else self.path, where=str(prim.GetPath()))

    def attr_loc(self, attr):
        stack = attr.GetPropertyStack()
        if stack:
            return Loc(self.layer_name(stack[0].layer), where=str(attr.GetPath()))
        return Loc(self.prim_loc(attr.GetPrim()).file, where=str(attr.GetPath()))

    def top_name(self, stem):
        from mtlxgen.base.identifiers import unique_identifier
        name = stem if stem not in self.taken else unique_identifier(stem, set(self.taken))
        self.taken.add(name)
        return name

    def scope_of(self, prim):
        """The NodeGraph prim whose nodegraph holds this shader or nodegraph prim (None: the document)."""
        from pxr import UsdShade
        p = prim.GetParent()
        while p and p.IsValid() and not p.IsPseudoRoot():
            if p.IsA(UsdShade.Material):
                return None
            if p.IsA(UsdShade.NodeGraph):
                return str(p.GetPath())
            p = p.GetParent()
        return None

    def scope(self, path):
        if path not in self.scopes:
            prim = self.stage.GetPrimAtPath(path)
            name = self.top_name(element_name(path))
            g = NodeGraph(name=name, loc=self.prim_loc(prim))
            self.doc.nodegraphs[name] = g
            self.doc.order.append(name)
            self.scopes[path] = _Scope(path, g)
        return self.scopes[path]

    def node_name(self, scope_path, prim):
        key = (scope_path, str(prim.GetPath()))
        if key not in self.names:
            if scope_path is None:
                self.names[key] = self.top_name(element_name(prim.GetPath()))
            else:
                sc = self.scope(scope_path)
                rel = str(prim.GetPath())[len(scope_path):]
                stem = element_name(rel)
                name = stem
                k = 1
                while name in sc.taken:
                    k += 1
                    name = "%s%d" % (stem, k)
                sc.taken.add(name)
                self.names[key] = name
        return self.names[key]

    # ---------- the stage ----------
    def read(self):
        from pxr import Usd, UsdShade
        info = self.doc.usd
        if self.options.variants:
            info.problems += select_variants(self.stage, self.path, self.options.variants)
        info.problems += self.composition_problems()
        materials = [p for p in self.stage.Traverse(Usd.TraverseInstanceProxies()) if p.IsA(UsdShade.Material)]
        mtlx_refs = self.mtlx_references()
        # element names first, so that materials keep their plain names
        for prim in materials:
            path = str(prim.GetPath())
            element = self.top_name(element_name(path))
            info.materials[element] = MaterialInfo(element=element, prim=path, loc=self.prim_loc(prim))
            info.by_prim[path] = element
        for ref in mtlx_refs:
            self.read_mtlx_reference(*ref)
        for prim in materials:
            self.material(prim, info.materials[info.by_prim[str(prim.GetPath())]])

    def composition_problems(self):
        out = []
        try:
            errors = self.stage.GetCompositionErrors()
        except AttributeError:          # older usd-core
            return out
        for e in errors:
            text = " ".join(str(e).split())
            if re.search(r"\.mtlx@", text, re.I):       # read by us (read_mtlx_reference)
                continue
            site = getattr(e, "rootSite", None)
            where = str(site.path) if site is not None and str(getattr(site, "path", "")) else None
            out.append((Loc(self.path, 0, where), "composition: %s" % text))
        return out

    # ---------- materials ----------
    def material(self, prim, info):
        from pxr import UsdShade
        mat = UsdShade.Material(prim)
        outputs = {"mtlx": mat.GetSurfaceOutput("mtlx"), "universal": mat.GetSurfaceOutput()}
        present = {k: o for k, o in outputs.items() if o and o.GetAttr().IsValid() and o.GetAttr().HasAuthoredConnections()}
        info.contexts = tuple(k for k in RENDER_CONTEXTS if k in present)
        want = self.options.render_context
        context = want if want in present else next(iter(present), None)
        node = Node(category="surfacematerial", name=info.element, type="material", loc=info.loc)
        self.doc.nodes[info.element] = node
        self.doc.order.append(info.element)
        if context is None:
            info.problems.append((info.loc, "material has no connected surface output (outputs:mtlx:surface or "
                                            "outputs:surface)"))
            return
        info.context = context
        out = present[context]
        key = ("material", info.element)
        problems, notes, ignored, deps = [], [], [], []
        port = self.port_for(out, "surfacematerial", "surfaceshader", "surfaceshader", None, problems, deps,
                             consumer=info.element)
        if port is not None:
            node.inputs["surfaceshader"] = port
        disp = self.displacement(mat, context, info, problems, deps)
        if disp is not None:
            node.inputs["displacementshader"] = disp
        self.items[key] = (problems, notes, ignored, deps, [])
        self.collect(key, info)

    def displacement(self, mat, context, info, problems, deps):
        """The port of the material's displacementshader input, from its displacement output of the drawn
        context (outputs:mtlx:displacement or outputs:displacement); None where none is connected.

        A universal displacement connects to a UsdPreviewSurface's outputs:displacement: the surface moves
        along its normal by the shader's `displacement` input (UsdPreviewSurface Specification 2.5), which is
        a displacement node (ND_displacement_float, scale 1) reading that input. A MaterialX network's
        connects to a displacementshader (ND_displacement_float / _vector3), read as any node."""
        from pxr import UsdShade
        out = mat.GetDisplacementOutput("mtlx" if context == "mtlx" else "")
        if not out or not out.GetAttr().IsValid() or not out.GetAttr().HasAuthoredConnections():
            return None
        target = self.resolve(out, None, problems)
        if target is None or target[0] == "value":
            return None
        if target[0] == "node" and self.spec(target[1]).shader_id == "UsdPreviewSurface":
            amount = UsdShade.Shader(target[1]).GetInput("displacement")
            if not amount:
                return None         # nothing authored: the default, 0, moves nothing
            name = self.top_name(info.element + "_displacement")
            loc = self.attr_loc(out.GetAttr())
            dnode = Node(category="displacement", name=name, type="displacementshader", loc=loc,
                         nodedef="ND_displacement_float")
            dport = self.port_for(amount, "displacement", "displacement", "float", None, problems, deps,
                                  consumer=name)
            if dport is None:
                return None
            dnode.inputs["displacement"] = dport
            self.doc.nodes[name] = dnode
            self.doc.order.append(name)
            return Port(name="displacementshader", type="displacementshader", loc=loc, nodename=name)
        return self.port_for(out, "surfacematerial", "displacementshader", "displacementshader", None, problems,
                             deps, consumer=info.element)

    def collect(self, start, info):
        """Convert everything the material reaches (work list, no recursion) and gather its problems."""
        seen, stack = set(), [start]
        while stack:
            key = stack.pop()
            if key in seen:
                continue
            seen.add(key)
            if key not in self.items:
                self.items[key] = self.convert(key)
            problems, notes, ignored, deps, shaders = self.items[key]
            for p in problems:
                if p not in info.problems:
                    info.problems.append(p)
            for p in notes:
                if p not in info.notes:
                    info.notes.append(p)
            for p in ignored:
                if p not in info.ignored:
                    info.ignored.append(p)
            for s in shaders:
                if s not in info.shaders:
                    info.shaders.append(s)
                    if s[1] == "UsdPrimvarReader_float2":
                        name = self.varname(s[0])
                        if name and name not in info.primvars:
                            info.primvars.append(name)
                    if s[1] in _VERTEX_READERS or s[1].startswith("ND_geompropvalue_"):
                        name = self.varname(s[0], "geomprop" if s[1].startswith("ND_") else "varname")
                        if name and name not in info.vertex_primvars:
                            info.vertex_primvars.append(name)
            stack.extend(reversed(deps))

    def varname(self, prim_path, input_name="varname"):
        """The varname a primvar reader reads (through a connection to an interface input, as USD allows)."""
        from pxr import UsdShade
        inp = UsdShade.Shader(self.stage.GetPrimAtPath(prim_path)).GetInput(input_name)
        target = self.resolve(inp, None, []) if inp else None
        value = target[1].Get() if target and target[0] == "value" else None
        return str(value) if value else None

    def convert(self, key):
        problems, notes, ignored, deps, shaders = [], [], [], [], []
        kind = key[0]
        try:
            if kind == "shader":
                self.convert_shader(key[1], key[2], problems, notes, ignored, deps, shaders)
            elif kind == "ngoutput":
                self.convert_ng_output(key[1], key[2], problems, deps)
            elif kind == "nodegraph":
                self.convert_nodegraph(key[1], problems, notes, deps)
            elif kind == "matinput":
                self.convert_material_input(key[1], key[2], problems, notes, deps)
        except MtlxError as e:
            problems.extend(e.problems)
        except Exception as e:      # pxr's Tf.ErrorException: USD refusing something of this prim
            if type(e).__module__.split(".")[0] != "pxr":
                raise
            problems.append((Loc(self.path, where=key[-1] if isinstance(key[-1], str) else None),
                             "USD: %s" % _tf_message(e)))
        return problems, notes, ignored, deps, shaders

    # ---------- shader prims ----------
    def spec(self, prim):
        path = str(prim.GetPath())
        if path not in self.specs:
            self.specs[path] = self._spec(prim)
        return self.specs[path]

    def _nd_spec(self, nd, category, type_name, nodedef, shader_id, usd_preview):
        ins = {n: p.type for n, p in nd.inputs.items()}
        outs = {n: p.type for n, p in nd.outputs.items()}
        return _Spec(category, type_name, nodedef, ins, outs, shader_id, usd_preview, decl=nd)

    def _spec(self, prim):
        from pxr import UsdShade
        shader = UsdShade.Shader(prim)
        sid = shader.GetShaderId() or ""
        lib = self.lib
        if not sid:
            source = shader.GetImplementationSource()
            why = ("its implementation source is '%s', which mtlxgen cannot read" % source if source != "id"
                   else "it has no info:id")
            return _Spec(None, None, None, {}, {}, "", False, "shader %s: %s" % (prim.GetName(), why))
        if sid.startswith("ND_"):
            nd = lib.nodedefs.get(sid)
            if nd is None:
                return _Spec(None, None, None, {}, {}, sid, False,
                             "info:id '%s' names no MaterialX nodedef in the libraries" % sid)
            return self._nd_spec(nd, nd.category, nd.type, sid, sid, False)
        seed = {"UsdPreviewSurface": "ND_usd_seed_UsdPreviewSurface_surfaceshader",
                "UsdUVTexture": "ND_usd_seed_UsdUVTexture", "UsdTransform2d": "ND_UsdTransform2d"}.get(sid)
        if seed is not None and seed in lib.nodedefs:
            nd = lib.nodedefs[seed]
            spec = self._nd_spec(nd, sid, nd.type, None, sid, True)
            if sid == "UsdUVTexture":
                spec.type = "multioutput"
            return spec
        if sid.startswith("UsdPrimvarReader_"):
            t = _PRIMVAR_TYPES.get(sid[len("UsdPrimvarReader_"):])
            nd = lib.nodedefs.get("ND_UsdPrimvarReader_%s" % t) if t else None
            if nd is not None:
                return self._nd_spec(nd, "UsdPrimvarReader", t, None, sid, True)
            return _Spec(None, None, None, {}, {}, sid, False, "info:id '%s': no primvar reader of that type" % sid)
        return _Spec(None, None, None, {}, {}, sid, False,
                     "unknown shader info:id '%s' (mtlxgen reads %s and MaterialX nodedef names, ND_*)"
                     % (sid, ", ".join(USD_SHADER_IDS)))

    def convert_shader(self, scope_path, prim_path, problems, notes, ignored, deps, shaders):
        from pxr import UsdShade
        prim = self.stage.GetPrimAtPath(prim_path)
        spec = self.spec(prim)
        shaders.append((prim_path, spec.shader_id or "?"))
        loc = self.prim_loc(prim)
        if spec.problem:
            problems.append((loc, spec.problem))
            return
        name = self.node_name(scope_path, prim)
        node = Node(category=spec.category, name=name, type=spec.type, loc=loc, nodedef=spec.nodedef)
        sc = self.scope(scope_path) if scope_path else self.scopes[None]
        if sc.graph is None:
            self.doc.nodes[name] = node
            self.doc.order.append(name)
        else:
            sc.graph.nodes[name] = node
        for inp in UsdShade.Shader(prim).GetInputs():
            iname = inp.GetBaseName()
            want = spec.inputs.get(iname)
            if want is None:
                if spec.usd_preview:
                    if inp.HasConnectedSource() or inp.GetAttr().HasAuthoredValue():
                        ignored.append((self.attr_loc(inp.GetAttr()), "input '%s' is not an input of %s: ignored"
                                        % (iname, spec.shader_id)))
                    continue
                want = mx_type_of(inp.GetTypeName()) or "string"
            port = self.port_for(inp, name, iname, want, scope_path, problems, deps, notes=notes, node_spec=spec,
                                 consumer=name)
            if port is not None:
                node.inputs[iname] = port

    # ---------- connections ----------
    def first_source(self, attr_api, problems):
        """(source prim, source name, is output) of a UsdShade Input/Output, or None; problems for
        connections to nothing."""
        from pxr import UsdShade
        sources, invalid = attr_api.GetConnectedSources()
        loc = self.attr_loc(attr_api.GetAttr())
        if invalid and not sources:
            declared = self.declared_output(invalid[0], loc)
            if declared is not None:
                return declared
        for path in invalid:
            prim = self.stage.GetPrimAtPath(path.GetPrimPath()) if path.IsPropertyPath() else None
            if prim and prim.IsValid() and (prim.IsA(UsdShade.Shader) or prim.IsA(UsdShade.NodeGraph)):
                problems.append((loc, "connects to <%s>, which <%s> does not declare (USD connects only to "
                                      "authored inputs and outputs)" % (path, path.GetPrimPath())))
            else:
                problems.append((loc, "connects to <%s>, which is not an input or output of a shader, nodegraph or "
                                      "material on the stage" % path))
        if not sources:
            return None
        s = sources[0]
        prim = s.source.GetPrim()
        return prim, s.sourceName, s.sourceType == UsdShade.AttributeType.Output

    def declared_output(self, path, loc):
        """(shader prim, output name, True) for a connection to an output a shader prim does not author but its
        definition declares (UsdPreviewSurface's outputs:displacement, a MaterialX nodedef's outputs:out): UsdShade
        resolves such a connection through the shader's registry definition, and so do we (warned). None for
        anything else."""
        from pxr import UsdShade
        if not path.IsPropertyPath() or not path.name.startswith("outputs:"):
            return None
        prim = self.stage.GetPrimAtPath(path.GetPrimPath())
        if not prim or not prim.IsValid() or not prim.IsA(UsdShade.Shader):
            return None
        name = path.name[len("outputs:"):]
        spec = self.spec(prim)
        if spec.problem or name not in _declared_outputs(spec):
            return None
        item = (loc, "connects to <%s>, which <%s> does not author: read as the output %s declares, as UsdShade "
                     "resolves it" % (path, path.GetPrimPath(), spec.shader_id))
        if item not in self.doc.warnings:
            self.doc.warnings.append(item)
        return prim, name, True

    def resolve(self, attr_api, scope_path, problems):
        """Follow a consumer's connection to what the consumer in `scope_path` reads:
        ("value", attr) | ("node", prim, output) | ("ngout", path, output) | ("ngin", name) |
        ("docin", material prim, name) | None (a problem was added)."""
        from pxr import UsdShade
        current = attr_api
        for _ in range(MAX_CHAIN):
            src = self.first_source(current, problems)
            if src is None:
                return ("value", current)
            prim, name, is_output = src
            path = str(prim.GetPath())
            loc = self.attr_loc(current.GetAttr())
            if prim.IsA(UsdShade.Material):
                if is_output:
                    problems.append((loc, "connects to output '%s' of material <%s>" % (name, path)))
                    return None
                nxt = UsdShade.Material(prim).GetInput(name)
                if not nxt:
                    problems.append((loc, "connects to <%s.inputs:%s>, which does not exist" % (path, name)))
                    return None
                if nxt.HasConnectedSource():
                    current = nxt
                    continue
                return ("docin", prim, name)
            if prim.IsA(UsdShade.NodeGraph):
                ng = UsdShade.NodeGraph(prim)
                if is_output:
                    if path == scope_path:          # a node of the graph reading the graph's own output
                        out = ng.GetOutput(name)
                        if not out:
                            problems.append((loc, "connects to <%s.outputs:%s>, which does not exist" % (path, name)))
                            return None
                        current = out
                        continue
                    if not ng.GetOutput(name):
                        problems.append((loc, "connects to <%s.outputs:%s>, which does not exist" % (path, name)))
                        return None
                    return ("ngout", path, name)
                nxt = ng.GetInput(name)
                if not nxt:
                    problems.append((loc, "connects to <%s.inputs:%s>, which does not exist" % (path, name)))
                    return None
                if path == scope_path:
                    return ("ngin", name, path)
                current = nxt           # an interface input read from outside its graph: what it holds
                continue
            if prim.IsA(UsdShade.Shader):
                if not is_output:
                    nxt = UsdShade.Shader(prim).GetInput(name)
                    if nxt and nxt.HasConnectedSource():
                        current = nxt
                        continue
                    return ("value", nxt) if nxt else None
                return ("node", prim, name)
            problems.append((loc, "connects to <%s>, a %s, not a shader, nodegraph or material"
                             % (path, prim.GetTypeName() or "typeless prim")))
            return None
        problems.append((self.attr_loc(attr_api.GetAttr()), "connections pass through more than %d interface inputs"
                         % MAX_CHAIN))
        return None

    def source_type(self, target, problems, depth=0):
        """MaterialX type of what a resolved target produces (None where unknown)."""
        kind = target[0]
        if kind == "node":
            spec = self.spec(target[1])
            if spec.problem:
                return None
            if len(spec.outputs) == 1:
                return next(iter(spec.outputs.values()))
            return spec.outputs.get(target[2])
        if kind == "ngout":
            if depth > MAX_CHAIN:
                return None
            from pxr import UsdShade
            out = UsdShade.NodeGraph(self.stage.GetPrimAtPath(target[1])).GetOutput(target[2])
            inner = self.resolve(out, target[1], [])
            if inner is None or inner[0] == "value":
                return mx_type_of(out.GetTypeName())
            return self.source_type(inner, problems, depth + 1) or mx_type_of(out.GetTypeName())
        if kind == "ngin":
            from pxr import UsdShade
            inp = UsdShade.NodeGraph(self.stage.GetPrimAtPath(target[2])).GetInput(target[1])
            return self.interface_type(inp) if inp else None
        if kind == "docin":
            from pxr import UsdShade
            inp = UsdShade.Material(target[1]).GetInput(target[2])
            return mx_type_of(inp.GetTypeName())
        return None

    def port_for(self, attr_api, owner, name, want, scope_path, problems, deps, notes=None, node_spec=None,
                 consumer=None, kind="input"):
        """The Port for consumer input/output `name` (MaterialX type `want`) of `owner` in scope
        `scope_path`, from a UsdShade Input or Output. None where nothing is authored (defaults apply)."""
        attr = attr_api.GetAttr()
        loc = self.attr_loc(attr)
        target = self.resolve(attr_api, scope_path, problems)
        if target is None:
            return None
        if target[0] == "value":
            return self.value_port(target[1], name, want, loc, kind, notes, node_spec, problems)
        port = Port(name=name, type=want, loc=loc, kind=kind)
        src_type = self.source_type(target, problems)
        if target[0] == "ngin" and scope_path is not None:
            port.interfacename = target[1]
            deps.append(("nodegraph", scope_path))
        else:
            self.link(port, target, scope_path, problems, deps)
        if src_type is not None and src_type != want and _SAME_SIZE.get(src_type) == want and kind == "input":
            return self.convert_port(port, src_type, want, scope_path, consumer, name)
        if src_type is not None and src_type != want and kind == "output":
            port.type = src_type        # an output carries what it is connected to
        return port

    def link(self, port, target, scope_path, problems, deps):
        """Point `port` (in scope `scope_path`) at a node, nodegraph output or document input."""
        kind = target[0]
        if kind == "node":
            prim, out_name = target[1], target[2]
            src_scope = self.scope_of(prim)
            spec = self.spec(prim)
            if src_scope == scope_path:
                port.nodename = self.node_name(scope_path, prim)
                if len(spec.outputs) > 1 and not spec.problem:
                    if out_name not in spec.outputs:
                        problems.append((port.loc, "connects to output '%s' of <%s>, which %s does not have "
                                                   "(outputs: %s)" % (out_name, prim.GetPath(), spec.shader_id,
                                                                      ", ".join(spec.outputs))))
                    port.output = out_name
                deps.append(("shader", scope_path, str(prim.GetPath())))
                return
            if scope_path is None:
                # a top-level consumer reading a node inside a nodegraph: through an output of that graph
                out = self.synth_output(src_scope, prim, out_name, spec, deps)
                port.nodegraph, port.output = self.scope(src_scope).graph.name, out
                return
            self.through_input(port, target, scope_path, problems, deps)
            return
        if kind == "ngout":
            if scope_path is None:
                port.nodegraph, port.output = self.scope(target[1]).graph.name, target[2]
                deps.append(("ngoutput", target[1], target[2]))
                return
            self.through_input(port, target, scope_path, problems, deps)
            return
        if kind == "docin":
            name = self.doc_input(target[1], target[2], port.type, deps)
            if scope_path is None:
                port.interfacename = name
                return
            self.through_input(port, target, scope_path, problems, deps)
            return
        raise AssertionError(kind)

    def through_input(self, port, target, scope_path, problems, deps):
        """A consumer inside nodegraph `scope_path` reading something outside it: an input of that graph
        carries it in (one per source), the consumer reads the input."""
        key = (scope_path, target[0], str(target[1].GetPath()) if hasattr(target[1], "GetPath") else target[1],
               target[2])
        sc = self.scope(scope_path)
        name = self.synth.get(key)
        if name is None:
            stem = "in_%s_%s" % (element_name(key[2]), target[2])
            name = stem
            k = 1
            while name in sc.graph.inputs:
                k += 1
                name = "%s%d" % (stem, k)
            outer = Port(name=name, type=port.type, loc=port.loc, kind="input")
            self.link(outer, target, None, problems, deps)
            sc.graph.inputs[name] = outer
            self.synth[key] = name
        port.interfacename = name
        deps.append(("nodegraph", scope_path))

    def synth_output(self, scope_path, prim, out_name, spec, deps):
        """An output of nodegraph `scope_path` passing out one of its nodes' outputs."""
        key = (scope_path, "out", str(prim.GetPath()), out_name)
        sc = self.scope(scope_path)
        name = self.synth.get(key)
        if name is None:
            stem = "out_%s_%s" % (element_name(str(prim.GetPath())[len(scope_path):]), out_name)
            name = stem
            k = 1
            while name in sc.graph.outputs:
                k += 1
                name = "%s%d" % (stem, k)
            t = (next(iter(spec.outputs.values())) if len(spec.outputs) == 1 else spec.outputs.get(out_name)) or "float"
            out = Port(name=name, type=t, loc=self.prim_loc(prim), kind="output",
                       nodename=self.node_name(scope_path, prim),
                       output=out_name if len(spec.outputs) > 1 else None)
            sc.graph.outputs[name] = out
            self.synth[key] = name
        deps.append(("shader", scope_path, str(prim.GetPath())))
        deps.append(("nodegraph", scope_path))
        return name

    def convert_port(self, port, src_type, want, scope_path, consumer, name):
        """A `convert` node between a source of one 3- or 4-float type and a consumer of the other."""
        stem = "%s_%s_convert" % (consumer or "in", name)
        if scope_path is None:
            cname = self.top_name(stem)
        else:
            sc = self.scope(scope_path)
            cname, k = stem, 1
            while cname in sc.taken:
                k += 1
                cname = "%s%d" % (stem, k)
            sc.taken.add(cname)
        inner = Port(name="in", type=src_type, loc=port.loc, kind="input", nodename=port.nodename,
                     nodegraph=port.nodegraph, output=port.output, interfacename=port.interfacename)
        node = Node(category="convert", name=cname, type=want, loc=port.loc, inputs={"in": inner})
        if scope_path is None:
            self.doc.nodes[cname] = node
            self.doc.order.append(cname)
        else:
            self.scope(scope_path).graph.nodes[cname] = node
        return Port(name=port.name, type=want, loc=port.loc, kind=port.kind, nodename=cname)

    # ---------- values ----------
    def value_port(self, inp, name, want, loc, kind, notes, node_spec, problems):
        """A Port holding the value authored on `inp` (an input of the consumer, or the interface input or
        shader input the consumer's connection leads to); None where none is authored."""
        from pxr import Usd
        attr = inp.GetAttr()
        value = attr.Get()
        if value is None and attr.GetNumTimeSamples():
            value = attr.Get(Usd.TimeCode.EarliestTime())
        if value is None:
            return None
        vloc = self.attr_loc(attr)
        port = Port(name=name, type=want, loc=vloc if vloc.where != loc.where else loc, kind=kind)
        if want == "filename":
            text = self.asset(attr, value, notes if notes is not None else problems, node_spec)
            port.text = port.value = text
            cs = attr.GetColorSpace() if attr.HasColorSpace() else None
            port.colorspace = str(cs) if cs else None
            return port
        try:
            port.text = value_text(value, want)
            port.value = mxtypes.parse_value(want, port.text)
        except mxtypes.ValueError_ as e:
            port.error = "input '%s' of type %s: %s" % (name, want, e)
        return port

    def asset(self, attr, value, notes, node_spec):
        """The file an asset value names, as a path the renderer can open ('' for none). Packaged files are
        copied out; a file that cannot be found is a note (the fallback is drawn)."""
        authored = getattr(value, "path", str(value)) or ""
        if not authored:
            return ""
        resolved = getattr(value, "resolvedPath", "") or ""
        layer = self.authoring_layer(attr)
        if "<UDIM>" in authored or "<UVTILE>" in authored:
            return self.tiled_asset(attr, authored, layer, notes, node_spec)
        if resolved:
            local = self.local_file(resolved, attr, notes)
            if local is None:
                return ""
            why = self.image_problem(local)
            if why is not None:         # a FIFO, a device, a huge file, not an image: never bound; the fallback
                notes.append((self.attr_loc(attr), "texture '%s' is %s; drawing the fallback %s"
                              % (authored, why, self.fallback_text(attr, node_spec))))
                return ""
            return local
        anchored = _anchor(layer, authored)
        notes.append((self.attr_loc(attr), "texture '%s' not found (looked for %s); drawing the fallback %s"
                      % (authored, anchored, self.fallback_text(attr, node_spec))))
        return anchored if "[" not in anchored else ""     # (inside a package: no file beside it is meant)

    def image_problem(self, local):
        """images.image_problem of a texture file (its header read once per file)."""
        if local not in self.image_problems:
            from mtlxgen.base.images import image_problem
            self.image_problems[local] = image_problem(local)
        return self.image_problems[local]

    def authoring_layer(self, attr):
        for spec in attr.GetPropertyStack():
            if spec.HasDefaultValue() or spec.GetInfo("timeSamples"):
                return spec.layer
        stack = attr.GetPropertyStack()
        return stack[0].layer if stack else self.stage.GetRootLayer()

    def fallback_text(self, attr, node_spec):
        """What a reader draws instead of a missing file: UsdUVTexture's `fallback`, an image's `default`."""
        from pxr import UsdShade
        prim = attr.GetPrim()
        spec = node_spec
        name = "fallback" if spec is not None and spec.category == "UsdUVTexture" else "default"
        if spec is None or name not in spec.inputs:
            return "(the node's default)"
        inp = UsdShade.Shader(prim).GetInput(name)
        value = inp.Get() if inp else None
        if value is not None:
            try:
                return "(%s)" % value_text(value, spec.inputs[name])
            except mxtypes.ValueError_:
                pass
        decl = spec.decl.inputs.get(name) if spec.decl is not None else None
        if decl is not None and decl.text:
            return "(%s)" % decl.text
        return "(zero)" if name == "default" else "(0, 0, 0, 1)"

    def tiled_asset(self, attr, authored, layer, notes, node_spec):
        token = "<UDIM>" if "<UDIM>" in authored else "<UVTILE>"
        anchored = _anchor(layer, authored)
        pattern = r"\d{4}" if token == "<UDIM>" else r"u\d+_v\d+"
        if anchored.endswith("]") and "[" in anchored:      # inside a package: copy the tiles out
            package, inner = _split_package(anchored)
            from pxr import Sdf
            try:
                names = Sdf.ZipFile.Open(package).GetFileNames()
            except Exception:
                names = []
            regex = re.compile(re.escape(inner).replace(re.escape(token), pattern))
            tiles = [n for n in names if regex.fullmatch(n)]
            copied = [self.local_file("%s[%s]" % (package, n), attr, notes) for n in tiles]
            if tiles and all(copied):       # copies keep the tile numbers: the pattern finds them
                return os.path.join(self.package_folder(package), _packaged_name(inner))
        else:
            folder, base = os.path.split(anchored)
            regex = re.compile(re.escape(base).replace(re.escape(token), pattern))
            try:
                found = any(regex.fullmatch(n) for n in os.listdir(folder or "."))
            except OSError:
                found = False
            if found:
                return anchored
        notes.append((self.attr_loc(attr), "no tiles of '%s' found (looked for %s); drawing the fallback %s"
                      % (authored, anchored, self.fallback_text(attr, node_spec))))
        return anchored

    # ---------- packages (.usdz) ----------
    def cache_folder(self):
        if self.cache_dir is None:
            base = os.environ.get("MTLXGEN_CACHE") or os.path.join(os.path.expanduser("~"), ".cache", "mtlxgen")
            self.cache_dir = os.path.join(base, "usdz")
        return self.cache_dir

    def package_folder(self, package):
        try:
            st = os.stat(package)
            stamp = "%s|%d|%d" % (os.path.realpath(package), st.st_size, st.st_mtime_ns)
        except OSError:
            stamp = package
        digest = hashlib.sha256(stamp.encode("utf-8", "surrogateescape")).hexdigest()[:20]
        return os.path.join(self.cache_folder(), digest)

    def local_file(self, resolved, attr, notes):
        """A resolved path a file reader can open: packaged files ("a.usdz[tex.png]") are copied to the
        cache once; others are returned as they are."""
        if not (resolved.endswith("]") and "[" in resolved):
            return resolved
        package, inner = _split_package(resolved)
        target = os.path.join(self.package_folder(package), _packaged_name(inner))
        if os.path.isfile(target):
            return target
        from pxr import Ar
        try:
            asset = Ar.GetResolver().OpenAsset(Ar.ResolvedPath(resolved))
            size = asset.GetSize() if asset else None
            if size is None:
                raise OSError("cannot open it")
            if size > MAX_PACKAGED_BYTES:
                raise OSError("%d bytes, more than the %d read from a package" % (size, MAX_PACKAGED_BYTES))
            data = asset.GetBuffer()
            os.makedirs(os.path.dirname(target), exist_ok=True)
            tmp = "%s.%d.tmp" % (target, os.getpid())
            with open(tmp, "wb") as f:
                f.write(data)
            os.replace(tmp, target)
            return target
        except Exception as e:
            notes.append((self.attr_loc(attr), "cannot read '%s' from the package %s: %s" % (inner, package, e)))
            return None

    # ---------- nodegraphs and material inputs ----------
    def convert_nodegraph(self, path, problems, notes, deps):
        """The nodegraph of a NodeGraph prim with its interface inputs (values, or what they connect to)."""
        from pxr import UsdShade
        sc = self.scope(path)
        ng = UsdShade.NodeGraph(self.stage.GetPrimAtPath(path))
        for inp in ng.GetInputs():
            name = inp.GetBaseName()
            if name in sc.graph.inputs:
                continue
            want = self.interface_type(inp)
            # every nodegraph is a top-level one: what its inputs connect to is read at the document level
            # (a graph inside a graph reads through the outer graph's ports, followed to their sources)
            port = self.port_for(inp, sc.graph.name, name, want, None, problems, deps, notes=notes,
                                 consumer=sc.graph.name)
            if port is None:
                port = Port(name=name, type=want, loc=self.attr_loc(inp.GetAttr()), kind="input")
                self.default_from_consumers(port, inp)
            sc.graph.inputs[name] = port

    def interface_type(self, inp):
        """The type of a NodeGraph/Material interface input: its Sdf type, made a colour (or vector) where
        the shader inputs reading it say so."""
        t = mx_type_of(inp.GetTypeName()) or "float"
        other = _SAME_SIZE.get(t)
        if other is None:
            return t
        for prim in self.consumers_of(inp):
            spec = self.spec(prim[0])
            ct = spec.inputs.get(prim[1])
            if ct == other:
                return other
            if ct == t:
                return t
        return t

    def consumers_of(self, inp):
        """(shader prim, input name) of shader inputs below the interface's prim connected to `inp`."""
        from pxr import Usd, UsdShade
        owner = inp.GetAttr().GetPrim()
        out = []
        for prim in Usd.PrimRange(owner):
            if not prim.IsA(UsdShade.Shader):
                continue
            for si in UsdShade.Shader(prim).GetInputs():
                for s in si.GetConnectedSources()[0]:
                    if s.source.GetPrim() == owner and s.sourceName == inp.GetBaseName():
                        out.append((prim, si.GetBaseName()))
        return out

    def convert_ng_output(self, path, out_name, problems, deps):
        from pxr import UsdShade
        sc = self.scope(path)
        if out_name in sc.graph.outputs:
            return
        out = UsdShade.NodeGraph(self.stage.GetPrimAtPath(path)).GetOutput(out_name)
        want = self.source_type(("ngout", path, out_name), problems) or mx_type_of(out.GetTypeName()) or "float"
        before = len(problems)
        port = self.port_for(out, sc.graph.name, out_name, want, path, problems, deps, kind="output",
                             consumer=sc.graph.name)
        if port is None:
            port = Port(name=out_name, type=want, loc=self.attr_loc(out.GetAttr()), kind="output")
            if len(problems) == before:
                problems.append((port.loc, "output '%s' of nodegraph <%s> is not connected" % (out_name, path)))
        sc.graph.outputs[out_name] = port
        deps.append(("nodegraph", path))

    def doc_input(self, mprim, name, want, deps):
        """The document input standing for material `mprim`'s interface input `name`."""
        key = ("docinput", str(mprim.GetPath()), name)
        if key not in self.synth:
            info = self.doc.usd.materials.get(self.doc.usd.by_prim.get(str(mprim.GetPath()), ""))
            stem = "%s_%s" % (info.element if info else element_name(mprim.GetPath()), name)
            self.synth[key] = self.top_name(stem)
        deps.append(("matinput", str(mprim.GetPath()), name))
        return self.synth[key]

    def convert_material_input(self, mpath, name, problems, notes, deps):
        from pxr import UsdShade
        mprim = self.stage.GetPrimAtPath(mpath)
        docname = self.synth[("docinput", mpath, name)]
        if docname in self.doc.inputs:
            return
        inp = UsdShade.Material(mprim).GetInput(name)
        want = self.interface_type(inp)
        port = self.value_port(inp, docname, want, self.attr_loc(inp.GetAttr()), "input", notes, None, problems)
        if port is None:
            port = Port(name=docname, type=want, loc=self.attr_loc(inp.GetAttr()), kind="input")
            self.default_from_consumers(port, inp)
        self.doc.inputs[docname] = port

    def default_from_consumers(self, port, inp):
        """An interface input without a value holds the default of the first shader input reading it."""
        for prim, name in self.consumers_of(inp):
            spec = self.spec(prim)
            decl = spec.decl.inputs.get(name) if spec.decl is not None else None
            if decl is not None and decl.value is not None and decl.type == port.type:
                port.value, port.text = decl.value, decl.text
                return

    # ---------- .mtlx references ----------
    def mtlx_references(self):
        """(prim, .mtlx path, reference target path, loc) for every reference or payload to a .mtlx file in
        the composed prims' specs (USD cannot compose them without MaterialX's plugin)."""
        from pxr import Sdf, Usd
        out, seen = [], set()
        for prim in self.stage.Traverse(Usd.TraverseInstanceProxies()):
            for spec in prim.GetPrimStack():
                items = []
                if spec.hasReferences:
                    items += list(spec.referenceList.GetAddedOrExplicitItems())
                if spec.hasPayloads:
                    items += list(spec.payloadList.GetAddedOrExplicitItems())
                for ref in items:
                    asset = ref.assetPath or ""
                    if not asset.lower().endswith(".mtlx"):
                        continue
                    try:
                        full = Sdf.ComputeAssetPathRelativeToLayer(spec.layer, asset)
                    except Exception:
                        full = os.path.join(os.path.dirname(spec.layer.realPath or ""), asset)
                    key = (str(prim.GetPath()), full, str(ref.primPath))
                    if key in seen:
                        continue
                    seen.add(key)
                    loc = Loc(self.layer_name(spec.layer), where=str(prim.GetPath()))
                    out.append((prim, full, str(ref.primPath), loc, asset))
        return out

    def read_mtlx_reference(self, prim, mtlx_path, target, loc, authored):
        """Materials of a referenced .mtlx document, read by our reader and merged under the names of the
        prim paths MaterialX's file-format plugin would give them."""
        from mtlxgen.read.document import load_upgraded
        from mtlxgen.read.document import renderable_elements
        info = self.doc.usd
        base = str(prim.GetPath())
        local = self.local_file(mtlx_path, prim, info.problems) if "[" in mtlx_path else mtlx_path
        if not local or not os.path.lexists(local):
            info.problems.append((loc, "references MaterialX document '%s', which cannot be found (looked for %s)"
                                  % (authored, mtlx_path)))
            return
        why = regular_file_problem(local, "text")
        if why is not None:         # a FIFO, a device, a dangling link: never opened
            info.problems.append((loc, "references MaterialX document '%s', which is %s" % (authored, why)))
            return
        try:
            sub = load_upgraded(local, self.library_dirs)
        except MtlxError as e:
            info.problems.extend(e.problems)
            return
        materials = [n for n in renderable_elements(sub) if sub.nodes.get(n) is not None
                     and sub.nodes[n].type == "material"]
        t = target.rstrip("/")
        if t in ("", "/MaterialX"):
            where = {m: "%s/Materials/%s" % (base, m) for m in materials}
        elif t == "/MaterialX/Materials":
            where = {m: "%s/%s" % (base, m) for m in materials}
        elif t.startswith("/MaterialX/Materials/") and t.count("/") == 3:
            chosen = t.rsplit("/", 1)[1]
            if chosen not in materials:
                info.problems.append((loc, "references <%s> in '%s', which has no material '%s' (materials: %s)"
                                      % (t, authored, chosen, ", ".join(materials) or "none")))
                return
            where = {chosen: base}
        else:
            info.problems.append((loc, "references <%s> in MaterialX document '%s': mtlxgen reads references to "
                                       "</MaterialX>, </MaterialX/Materials> and </MaterialX/Materials/NAME>"
                                  % (t, authored)))
            return
        if not where:
            info.problems.append((loc, "references MaterialX document '%s', which has no material" % authored))
            return
        renamed = self.merge(sub, local, {m: None for m in where})
        for m, prim_path in where.items():
            if prim_path in info.by_prim:
                info.problems.append((loc, "material <%s> from '%s' is also defined on the stage; the stage's is drawn"
                                      % (prim_path, authored)))
                continue
            element = self.top_name(element_name(prim_path))
            node = self.doc.nodes.pop(renamed[m])
            node.name = element
            self.doc.nodes[element] = node
            self.doc.order.append(element)
            mi = MaterialInfo(element=element, prim=prim_path, loc=node.loc, context="mtlx", contexts=("mtlx",),
                              source=local)
            for port in node.inputs.values():
                shader = self.doc.nodes.get(port.nodename) if port.nodename else None
                if shader is not None:
                    mi.shaders.append(("%s (%s)" % (port.nodename, os.path.basename(local)),
                                       shader.nodedef or shader.category))
            info.materials[element] = mi
            info.by_prim[prim_path] = element

    def merge(self, sub, mtlx_path, keep_materials):
        """Copy document `sub` into the stage document under fresh top-level names; returns {old: new} for
        its top-level nodes. Material nodes not in `keep_materials` are left out; file names are made
        absolute against the .mtlx file's folder (where our reader would have looked for them)."""
        from mtlxgen.base.resolve import resolve_file
        prefix = element_name(os.path.splitext(os.path.basename(mtlx_path))[0])
        ren_nodes, ren_graphs, ren_inputs = {}, {}, {}
        for name in sub.nodes:
            if sub.nodes[name].type == "material" and name not in keep_materials:
                continue
            ren_nodes[name] = self.top_name("%s_%s" % (prefix, name))
        for name in sub.nodegraphs:
            ren_graphs[name] = self.top_name("%s_%s" % (prefix, name))
        for name in sub.inputs:
            ren_inputs[name] = self.top_name("%s_%s" % (prefix, name))

        def fix(port, top):
            if port.nodegraph and port.nodegraph in ren_graphs:
                port.nodegraph = ren_graphs[port.nodegraph]
            if top and port.nodename and port.nodename in ren_nodes:
                port.nodename = ren_nodes[port.nodename]
            if top and port.interfacename and port.interfacename in ren_inputs:
                port.interfacename = ren_inputs[port.interfacename]
            if port.type == "filename" and port.text and not os.path.isabs(port.text):
                found = resolve_file(port.text, mtlx_path) if "<" not in port.text else None
                full = found or os.path.join(os.path.dirname(os.path.abspath(mtlx_path)), port.text)
                port.text = port.value = full

        for old, new in ren_nodes.items():
            node = sub.nodes[old]
            node.name = new
            for p in node.inputs.values():
                fix(p, True)
            self.doc.nodes[new] = node
            self.doc.order.append(new)
        for old, new in ren_graphs.items():
            g = sub.nodegraphs[old]
            g.name = new
            for p in g.inputs.values():
                fix(p, True)
            for p in g.outputs.values():
                fix(p, False)
            for n in g.nodes.values():
                for p in n.inputs.values():
                    fix(p, False)
            self.doc.nodegraphs[new] = g
            self.doc.order.append(new)
        for old, new in ren_inputs.items():
            p = sub.inputs[old]
            p.name = new
            fix(p, True)
            self.doc.inputs[new] = p
        for nd in sub.nodedefs.values():
            for p in nd.inputs.values():
                fix(p, False)
        for kind in ("nodedefs", "implementations", "structs", "geompropdefs", "unitdefs"):
            target = getattr(self.doc, kind)
            for k, v in getattr(sub, kind).items():
                target.setdefault(k, v)
        return ren_nodes


def _anchor(layer, authored):
    """An asset path anchored to the layer that authored it, whether or not the file exists (USD's resolver
    leaves a path it cannot find as written): "/dir/of/layer/x.png", or "/a/b.usdz[x.png]" in a package."""
    import posixpath
    full = layer.ComputeAbsolutePath(authored) if layer is not None else authored
    if layer is None or os.path.isabs(full) or full.endswith("]"):
        return full
    real = layer.realPath or layer.identifier or ""
    if real.endswith("]") and "[" in real:              # a layer inside a package
        package, inner = _split_package(real)
        return "%s[%s]" % (package, posixpath.normpath(posixpath.join(posixpath.dirname(inner), authored)))
    if real.lower().endswith(".usdz"):                  # a package's root layer
        return "%s[%s]" % (real, posixpath.normpath(authored))
    return os.path.normpath(os.path.join(os.path.dirname(real), authored))


def _split_package(resolved):
    """"/a/b.usdz[x/y.png]" -> ("/a/b.usdz", "x/y.png") (the outermost package)."""
    i = resolved.index("[")
    return resolved[:i], resolved[i + 1:-1]


def _packaged_name(inner):
    """A file name for a packaged file's copy: its path inside the package with folders joined by '__' (no
    '..' or separators survive), extension kept."""
    parts = [p for p in re.split(r"[\\/\[\]]+", inner) if p not in ("", ".", "..")]
    return "__".join(parts) or "file"
