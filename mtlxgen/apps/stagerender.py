"""`mtlxgen render SCENE.usda --geometry stage`: the stage's own meshes, each with the shader of its bound
material, drawn from the stage's camera (or a framing one) into one image, besides the sphere per material.

Read with usd-core: every visible UsdGeomMesh of purpose default or render (instance proxies too), its points,
faces (polygons as fans), normals (`primvars:normals` or `normals`, any interpolation; smooth ones computed
where none are authored), the texture coordinates its material's primvar readers name (else `st`, else the
first float2 primvar) as the renderer's one texcoord stream, tangents from those, its world transform, and
its material binding (`ComputeBoundMaterial`, GeomSubsets with their own bindings split the faces). The
primvars its materials' primvar readers (float, float2, float3, float4, int) and MaterialX geompropvalue nodes
name are bound as the vertex attributes the shaders read (the manifest's "attributes" and "primvars"), any
interpolation on a mesh, constant ones on an implicit Sphere or Cube, so readers of two texture coordinate sets
each read their own; a reader whose primvar the mesh lacks draws the texcoord stream (float2) or its fallback. Meshes without a material draw a grey UsdPreviewSurface in their constant `displayColor`. Subdivision surfaces are
drawn as their control cage. A mesh whose data do not make triangles (face vertex indices out of range, counts
that do not add up to them, points that are not finite numbers) is not drawn and is a problem naming it; an empty
one (no points or faces) draws nothing, and is named only where nothing at all is drawn. A stage whose up axis is
Z is turned to Y up (the lighting's up) with its camera.
The camera is the first UsdGeomCamera on the stage; without one, a camera at (0, 0.3, 1) from the centre of
the meshes' bounds, far enough for a 45 degree view to hold them. The output is square: a camera's aperture
is fitted inside it (the wider of its two fields of view on both axes).
"""
import math
import os
import tempfile
from mtlxgen.base.records import dataclass, field

import numpy as np

from mtlxgen.base.diagnostics import Loc, MtlxError

MAX_CORNERS = 2 * 10 ** 7           # face corners of all meshes together (memory: ~1 GB of attributes)
MAX_VERTEX_PRIMVARS = 8             # primvars of one mesh bound as vertex attributes (GL has 16 attributes at least)
FRAMING_FOV = 45.0
_Z_UP = np.array([[1, 0, 0, 0], [0, 0, 1, 0], [0, -1, 0, 0], [0, 0, 0, 1]], dtype=np.float64)   # Z up -> Y up


@dataclass
class MeshDraw:
    prim: str
    attrs: dict                     # vertex attribute name -> float32 (n, k) array, one row per face corner
    groups: list                    # [(element or None, int32 triangle corner indices)]
    world: np.ndarray               # 4x4, column vectors
    color: tuple = (0.18, 0.18, 0.18)
    double_sided: bool = False      # USD's default: back faces are not drawn
    primvars: dict = field(default_factory=dict)    # primvar name -> float64 (n, k), one row per face corner


@dataclass
class StageView:
    meshes: list
    view: np.ndarray                # 4x4 world -> eye
    projection: np.ndarray          # 4x4 eye -> clip
    eye: tuple
    camera: str                     # the camera's prim path, or "framing"
    problems: list = field(default_factory=list)


def _time(stage):
    from pxr import Usd
    return stage.GetStartTimeCode() if stage.HasAuthoredTimeCodeRange() else Usd.TimeCode.Default()


def read_view(path, library_dirs=(), options=None):
    """The meshes and camera of a USD stage (StageView); material prims are matched to the elements
    usdstage.load names."""
    from pxr import Usd, UsdGeom

    from mtlxgen.read import usdstage
    doc = usdstage.load(path, library_dirs, options)
    info = doc.usd
    with usdstage._quiet_stderr():
        stage, layers = usdstage._open(path)       # layers: held while the stage is read
        if info.options.variants:
            usdstage.select_variants(stage, path, info.options.variants)
        time = _time(stage)
        z_up = UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.z
        up = _Z_UP if z_up else np.eye(4)
        cache = UsdGeom.XformCache(time)
        meshes, problems, skipped, empty, corners = [], [], [], [], 0
        camera = None
        for prim in stage.Traverse(Usd.TraverseInstanceProxies()):
            img = UsdGeom.Imageable(prim)
            if prim.IsA(UsdGeom.Camera) and camera is None:
                camera = prim
                continue
            if not (prim.IsA(UsdGeom.Mesh) or prim.IsA(UsdGeom.Sphere) or prim.IsA(UsdGeom.Cube)):
                continue
            if img.ComputeVisibility(time) == UsdGeom.Tokens.invisible:
                continue
            if img.ComputePurpose() not in (UsdGeom.Tokens.default_, UsdGeom.Tokens.render):
                continue
            try:
                draw = _mesh(prim, info, time, problems, MAX_CORNERS - corners)
            except _Skip as e:      # an empty mesh draws nothing, rightly: said only where nothing is drawn
                where = Loc(path, where=str(prim.GetPath()))
                (empty if e.empty else skipped).append((where, "mesh not drawn: %s" % e))
                continue
            corners += len(draw.attrs["i_position"])
            if corners > MAX_CORNERS:
                raise MtlxError((Loc(path, 0), "the stage's meshes have more than %d face corners" % MAX_CORNERS))
            draw.world = up @ np.array(cache.GetLocalToWorldTransform(prim), dtype=np.float64).T
            meshes.append(draw)
        if not meshes:      # the meshes there are, each with what is wrong with it; else that there is none
            raise MtlxError(skipped + empty or
                            [(Loc(path, 0), "--geometry stage: no visible UsdGeomMesh on the stage")])
        problems = skipped + problems
        if camera is not None:
            view, projection, eye = _camera(camera, time, up)
            name = str(camera.GetPath())
        else:
            view, projection, eye = _framing(meshes)
            name = "framing"
    return StageView(meshes, view, projection, eye, name, problems)


class _Skip(Exception):
    """A mesh that is not drawn, and why; `empty`: it has nothing to draw (no points or faces), not an error."""

    def __init__(self, why, empty=False):
        super().__init__(why)
        self.empty = empty


def _expand(values, interpolation, idx, face_of_corner, what):
    """Per-corner rows of a primvar or attribute of the given interpolation."""
    values = np.asarray(values, dtype=np.float64)
    if values.ndim == 1:
        values = values[:, None]
    n = len(idx)
    if interpolation in ("vertex", "varying"):
        if len(values) <= idx.max(initial=0):
            raise _Skip("%s has %d values for %d points" % (what, len(values), idx.max(initial=0) + 1))
        return values[idx]
    if interpolation == "faceVarying":
        if len(values) != n:
            raise _Skip("%s has %d values for %d face corners" % (what, len(values), n))
        return values
    if interpolation == "uniform":
        if len(values) <= face_of_corner.max(initial=0):
            raise _Skip("%s has %d values for %d faces" % (what, len(values), face_of_corner.max(initial=0) + 1))
        return values[face_of_corner]
    if len(values) < 1:
        raise _Skip("%s is empty" % what)
    return np.repeat(values[:1], n, axis=0)


def _normalize(v):
    length = np.linalg.norm(v, axis=-1, keepdims=True)
    return np.where(length > 1e-20, v / np.maximum(length, 1e-20), 0.0)


def _implicit(prim, time):
    """A UsdGeomSphere (radius) or UsdGeomCube (size) as triangles: (P, N, UV per corner, triangles)."""
    from pxr import UsdGeom
    from mtlxgen.draw.renderer import sphere
    if prim.IsA(UsdGeom.Sphere):
        radius = float(UsdGeom.Sphere(prim).GetRadiusAttr().Get(time) or 1.0)
        attrs, index = sphere(64, 32)
        P = attrs["i_position"].astype(np.float64) * radius
        return P, attrs["i_normal"].astype(np.float64), attrs["i_texcoord_0"].astype(np.float64), index.reshape(-1, 3)
    size = float(UsdGeom.Cube(prim).GetSizeAttr().Get(time) or 2.0) / 2.0
    P, N, UV, tris = [], [], [], []
    for axis in range(3):
        for sign in (1.0, -1.0):
            n = np.zeros(3)
            n[axis] = sign
            u = np.zeros(3)
            u[(axis + 1) % 3] = 1.0
            v = np.cross(n, u)
            base = len(P)
            for a, b in ((0, 0), (1, 0), (1, 1), (0, 1)):
                P.append((n + (2 * a - 1) * u + (2 * b - 1) * v) * size)
                N.append(n)
                UV.append((a, b))
            tris += [(base, base + 1, base + 2), (base, base + 2, base + 3)]
    return np.array(P), np.array(N), np.array(UV, dtype=np.float64), np.array(tris)


def _mesh(prim, info, time, problems, corners_left=MAX_CORNERS):
    """The MeshDraw of a Mesh, Sphere or Cube prim; _Skip saying what is wrong where it cannot be drawn."""
    from pxr import UsdGeom
    if not prim.IsA(UsdGeom.Mesh):
        P, N, UV, tris = _implicit(prim, time)
        groups, elements = _bindings(prim, info, 1, time, np.zeros(len(tris), dtype=np.int64))
        draw = _finish(prim, P, N, UV, tris, groups, time)
        draw.primvars = _vertex_primvars(prim, info, elements, time, None, None, len(P), problems)
        return draw
    mesh = UsdGeom.Mesh(prim)
    points = mesh.GetPointsAttr().Get(time)
    counts = mesh.GetFaceVertexCountsAttr().Get(time)
    indices = mesh.GetFaceVertexIndicesAttr().Get(time)
    for name, value in (("points", points), ("faceVertexCounts", counts), ("faceVertexIndices", indices)):
        if value is None or len(value) == 0:
            raise _Skip("it has no %s" % name, empty=True)
    if len(indices) > corners_left:
        raise MtlxError((Loc(info.path, where=str(prim.GetPath())), "the stage's meshes have more than %d face "
                                                                    "corners" % MAX_CORNERS))
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    counts = np.asarray(counts, dtype=np.int64)
    idx = np.asarray(indices, dtype=np.int64)
    if not np.isfinite(pts).all():
        raise _Skip("its points are not all finite numbers")
    if (counts < 0).any():
        raise _Skip("faceVertexCounts holds a negative count")
    if counts.sum() != len(idx):
        raise _Skip("faceVertexCounts sum to %d, faceVertexIndices has %d" % (counts.sum(), len(idx)))
    if idx.min() < 0 or idx.max() >= len(pts):
        raise _Skip("faceVertexIndices out of range: %d is not one of its %d points"
                    % (idx.min() if idx.min() < 0 else idx.max(), len(pts)))
    if not (counts >= 3).any():
        raise _Skip("it has no face of three or more vertices")
    faces = len(counts)
    face_of_corner = np.repeat(np.arange(faces), counts)
    starts = np.cumsum(counts) - counts
    ntri = np.maximum(counts - 2, 0)
    tri_face = np.repeat(np.arange(faces), ntri)
    k = np.arange(ntri.sum()) - np.repeat(np.cumsum(ntri) - ntri, ntri) + 1
    s0 = starts[tri_face]
    tris = np.stack([s0, s0 + k, s0 + k + 1], -1)
    if mesh.GetOrientationAttr().Get(time) == UsdGeom.Tokens.leftHanded:
        tris = tris[:, [0, 2, 1]]
    P = pts[idx]
    pv = UsdGeom.PrimvarsAPI(prim)
    # normals: the primvar, else the attribute, else smooth from the faces
    normal_pv = pv.GetPrimvar("normals")
    if normal_pv and normal_pv.HasAuthoredValue():
        N = _expand(normal_pv.ComputeFlattened(time), normal_pv.GetInterpolation(), idx, face_of_corner, "normals")
    elif mesh.GetNormalsAttr().HasAuthoredValue():
        N = _expand(mesh.GetNormalsAttr().Get(time), mesh.GetNormalsInterpolation(), idx, face_of_corner, "normals")
    else:
        fn = np.cross(P[tris[:, 1]] - P[tris[:, 0]], P[tris[:, 2]] - P[tris[:, 0]])
        acc = np.zeros_like(pts)
        for c in range(3):
            np.add.at(acc, idx[tris[:, c]], fn)
        N = _normalize(acc)[idx]
    N = _normalize(N[:, :3])
    # texture coordinates: the primvar the bound materials' readers name, else st, else any float2 one
    groups, elements = _bindings(prim, info, faces, time, tri_face)
    names = [v for e in elements if e in info.materials for v in info.materials[e].primvars] + ["st"]
    uv_pv = next((pv.GetPrimvar(n) for n in names if pv.HasPrimvar(n) and pv.GetPrimvar(n).HasAuthoredValue()), None)
    if uv_pv is None:
        uv_pv = next((p for p in pv.GetPrimvarsWithAuthoredValues()
                      if str(p.GetTypeName()).startswith(("texCoord2", "float2", "double2"))), None)
    if uv_pv is not None:
        UV = _expand(uv_pv.ComputeFlattened(time), uv_pv.GetInterpolation(), idx, face_of_corner, uv_pv.GetName())
        UV = UV[:, :2] if UV.shape[1] >= 2 else np.zeros((len(idx), 2))
    else:
        UV = np.zeros((len(idx), 2))
    draw = _finish(prim, P, N, UV, tris, groups, time)
    draw.primvars = _vertex_primvars(prim, info, elements, time, idx, face_of_corner, len(idx), problems)
    return draw


def _vertex_primvars(prim, info, elements, time, idx, face_of_corner, corners, problems):
    """{name: per-corner values} of the primvars the bound materials read as vertex attributes. A primvar whose values do not fit the mesh is a problem, and its readers draw their
    fallback; an implicit Sphere or Cube (idx None) takes constant primvars only."""
    from pxr import UsdGeom
    pv = UsdGeom.PrimvarsAPI(prim)
    names = []
    for e in elements:
        m = info.materials.get(e)
        names += [n for n in (m.vertex_primvars if m else ()) if n not in names]
    out = {}
    for name in names:
        primvar = pv.GetPrimvar(name) if pv.HasPrimvar(name) else None
        if primvar is None or not primvar.HasAuthoredValue():
            continue
        loc = Loc(info.path, where=str(primvar.GetAttr().GetPath()))
        if len(out) == MAX_VERTEX_PRIMVARS:
            problems.append((loc, "primvar not bound (its readers draw their fallback): the mesh's materials read "
                                  "more than %d primvars as vertex attributes" % MAX_VERTEX_PRIMVARS))
            continue
        interpolation = primvar.GetInterpolation()
        try:
            values = primvar.ComputeFlattened(time)
            if values is None:
                continue
            try:
                values = np.asarray(values, dtype=np.float64)
            except (TypeError, ValueError):
                raise _Skip("its values (%s) are not numbers" % primvar.GetTypeName()) from None
            if values.ndim == 1:
                values = values[:, None]
            if values.ndim != 2 or not np.isfinite(values).all() or (values.size and np.abs(values).max() > 3e38):
                raise _Skip("its values are not finite 32-bit numbers")
            if idx is None:
                if interpolation != UsdGeom.Tokens.constant:
                    raise _Skip("%s values on an implicit %s (drawn tessellated): only constant ones are read"
                                % (interpolation, prim.GetTypeName()))
                if len(values) < 1:
                    raise _Skip("it is empty")
                out[name] = np.repeat(values[:1], corners, axis=0)
            else:
                out[name] = _expand(values, interpolation, idx, face_of_corner, "it")
            if not str(primvar.GetTypeName()).startswith(("int", "uint", "uchar", "bool")):
                out[name] = out[name].astype(np.float32)        # what the attribute holds (ints stay exact)
        except _Skip as e:
            problems.append((loc, "primvar not bound (its readers draw their fallback): %s" % e))
    return out


def _finish(prim, P, N, UV, tris, groups, time):
    """Tangents, the vertex attributes and the display colour of a mesh's triangles."""
    from pxr import UsdGeom
    pv = UsdGeom.PrimvarsAPI(prim)
    # tangents along increasing u, from each triangle's positions and coordinates, made perpendicular to N
    e1, e2 = P[tris[:, 1]] - P[tris[:, 0]], P[tris[:, 2]] - P[tris[:, 0]]
    d1, d2 = UV[tris[:, 1]] - UV[tris[:, 0]], UV[tris[:, 2]] - UV[tris[:, 0]]
    det = d1[:, 0] * d2[:, 1] - d2[:, 0] * d1[:, 1]
    t = (e1 * d2[:, 1:2] - e2 * d1[:, 1:2]) * np.where(np.abs(det) > 1e-20, 1.0 / np.where(det == 0, 1, det), 0.0)[:, None]
    acc = np.zeros_like(P)
    for c in range(3):
        np.add.at(acc, tris[:, c], t)
    T = acc - N * (acc * N).sum(-1, keepdims=True)
    fallback = np.cross(N, np.where(np.abs(N[:, 1:2]) < 0.9, [[0.0, 1.0, 0.0]], [[1.0, 0.0, 0.0]]))
    T = _normalize(np.where(np.linalg.norm(T, axis=-1, keepdims=True) > 1e-12, T, fallback))
    B = np.cross(N, T)
    f4 = lambda a: np.ascontiguousarray(a, dtype="f4")
    attrs = {"i_position": f4(P), "i_normal": f4(N), "i_tangent": f4(T), "i_bitangent": f4(B), "i_texcoord_0": f4(UV)}
    color = (0.18, 0.18, 0.18)
    dc = pv.GetPrimvar("displayColor")
    if dc and dc.HasAuthoredValue():
        value = dc.ComputeFlattened(time)
        if value is not None and len(value):
            color = tuple(float(x) for x in value[0])
    groups = [(element, np.ascontiguousarray(tris[sel].reshape(-1), dtype="i4")) for element, sel in groups]
    sided = UsdGeom.Gprim(prim).GetDoubleSidedAttr().Get(time)
    return MeshDraw(str(prim.GetPath()), attrs, [g for g in groups if len(g[1])], np.eye(4), color, bool(sided))


def _bindings(prim, info, faces, time, tri_face):
    """[(element or None, triangle selector)] of a mesh and its bound GeomSubsets, and the elements."""
    from pxr import UsdShade
    api = UsdShade.MaterialBindingAPI(prim)

    def element_of(p):
        # the "full" purpose (final renders, as ours are), else the binding for all purposes
        material, _ = UsdShade.MaterialBindingAPI(p).ComputeBoundMaterial(UsdShade.Tokens.full)
        return info.by_prim.get(str(material.GetPath())) if material else None

    owner = np.full(faces, -1)
    groups, elements = [], []
    for i, subset in enumerate(api.GetMaterialBindSubsets()):
        ids = subset.GetIndicesAttr().Get(time)
        if ids is None:
            continue
        ids = np.asarray(ids, dtype=np.int64)
        ids = ids[(ids >= 0) & (ids < faces)]
        owner[ids] = i
        e = element_of(subset.GetPrim())
        groups.append((e, owner[tri_face] == i))
        elements.append(e)
    e = element_of(prim)
    groups.append((e, owner[tri_face] == -1))
    elements.append(e)
    return groups, [x for x in elements if x]


def _camera(prim, time, up):
    from pxr import UsdGeom
    cam = UsdGeom.Camera(prim).GetCamera(time)
    world = up @ np.array(cam.transform, dtype=np.float64).T
    view = np.linalg.inv(world)
    near, far = cam.clippingRange.min, cam.clippingRange.max
    near = max(near, 1e-4)
    far = max(far, near * 1.001)
    if cam.projection == cam.Orthographic:
        half = 0.05 * max(cam.horizontalAperture, cam.verticalAperture)    # apertures in tenths of a unit
        proj = np.zeros((4, 4))
        proj[0, 0] = proj[1, 1] = 1.0 / max(half, 1e-9)
        proj[2, 2], proj[2, 3], proj[3, 3] = -2.0 / (far - near), -(far + near) / (far - near), 1.0
    else:
        focal = max(cam.focalLength, 1e-9)
        half_tan = max(cam.horizontalAperture, cam.verticalAperture) / 2.0 / focal
        from mtlxgen.draw.renderer import perspective
        proj = perspective(math.degrees(2.0 * math.atan(half_tan)), 1.0, near, far)
    return view, proj, tuple(world[:3, 3])


def _framing(meshes):
    from mtlxgen.draw.renderer import look_at, perspective
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for m in meshes:
        p = m.attrs["i_position"].astype(np.float64)
        w = p @ m.world[:3, :3].T + m.world[:3, 3]
        lo, hi = np.minimum(lo, w.min(0)), np.maximum(hi, w.max(0))
    centre, radius = (lo + hi) / 2.0, max(np.linalg.norm(hi - lo) / 2.0, 1e-6)
    direction = np.array([0.0, 0.3, 1.0]) / np.linalg.norm([0.0, 0.3, 1.0])
    distance = radius / math.sin(math.radians(FRAMING_FOV / 2.0)) * 1.05
    eye = centre + direction * distance
    view = look_at(eye, centre, (0.0, 1.0, 0.0))
    proj = perspective(FRAMING_FOV, 1.0, max(distance - radius * 1.5, distance * 1e-3), distance + radius * 1.5)
    return view, proj, tuple(eye)


# ---------------------------------------------------------------- drawing

_FALLBACK = """<?xml version="1.0"?>
<materialx version="1.39">
  <UsdPreviewSurface name="display" type="surfaceshader">
    <input name="diffuseColor" type="color3" value="0.18, 0.18, 0.18" />
  </UsdPreviewSurface>
  <surfacematerial name="displayColor" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="display" />
  </surfacematerial>
</materialx>
"""


def fallback_shader(environment="fis"):
    """The shader of meshes without a material: a UsdPreviewSurface whose diffuseColor is set per mesh."""
    from mtlxgen import pipeline
    from mtlxgen.options import GenerateOptions
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "display_color.mtlx")
        with open(path, "w") as f:
            f.write(_FALLBACK)
        return pipeline.generate(path, GenerateOptions(usd_seed_rules=True, environment=environment))[0]


def render_stage(renderer, view, shaders, fallback):
    """Draw every mesh of `view` with the shader of its element (`shaders`: element -> Shader; `fallback` for
    meshes without one) into the renderer's framebuffer. Returns linear RGBA float32, row 0 on top."""
    r, ctx = renderer, renderer.ctx
    mgl = r.mgl
    ctx.__enter__()
    r.fbo.use()
    ctx.enable(mgl.DEPTH_TEST)
    ctx.clear(0.0, 0.0, 0.0, 0.0)
    camera = _StageCamera(view.eye, view.projection @ view.view)
    programs = {}
    try:
        for mesh in view.meshes:
            # USD's winding: counter-clockwise seen from the front (rightHanded; leftHanded meshes were turned)
            if mesh.double_sided or np.linalg.det(mesh.world[:3, :3]) == 0:
                ctx.disable(mgl.CULL_FACE)
            else:
                ctx.enable(mgl.CULL_FACE)
                ctx.front_face = "ccw" if np.linalg.det(mesh.world[:3, :3]) > 0 else "cw"
            buffers = {k: (ctx.buffer(v.tobytes()), "%df" % v.shape[1]) for k, v in mesh.attrs.items()}
            primvar_buffers = {}
            world = mesh.world
            for element, tris in mesh.groups:
                shader = shaders.get(element) if element else None
                shader = shader or fallback
                key = id(shader)
                if key not in programs:
                    programs[key] = r.prepare(shader.vertex, shader.fragment, shader.manifest, vertex_array=False)
                prog = programs[key].prog
                r.bind(programs[key], camera=camera, world=world)
                if shader is fallback:
                    for u in shader.manifest.get("uniforms", []):
                        if u["name"].endswith("diffuseColor") and u["name"] in prog:
                            prog[u["name"]].value = tuple(mesh.color[:3])
                index = ctx.buffer(tris.tobytes())
                content = [(buf, fmt, name) for name, (buf, fmt) in buffers.items() if name in prog]
                content += _bind_primvars(ctx, prog, shader.manifest, mesh, primvar_buffers)
                vao = ctx.vertex_array(prog, content, index)
                vao.render()
                vao.release()
                index.release()
            for buf, _ in list(buffers.values()) + list(primvar_buffers.values()):
                buf.release()
        raw = r.fbo.read(components=4, dtype="f4")
    finally:
        ctx.disable(mgl.CULL_FACE)
        ctx.front_face = "ccw"
        for prepared in programs.values():
            prepared.prog.release()
    return np.frombuffer(raw, dtype="f4").reshape(r.size, r.size, 4)[::-1].copy()


_GLSL_COMPONENTS = {"float": (1, "f4", "f"), "vec2": (2, "f4", "f"), "vec3": (3, "f4", "f"), "vec4": (4, "f4", "f"),
                    "int": (1, "i4", "i")}


def _bind_primvars(ctx, prog, manifest, mesh, cache):
    """Vertex-array entries for the mesh's primvars that the shader reads (its i_geomprop_NAME attributes:
    the seed's primvar readers, named in the manifest's "primvars", and MaterialX's geompropvalue nodes), and
    each seed reader's flag uniform: 1 where the mesh has its primvar, else 0 (the fallback). A primvar with
    fewer components than the attribute is padded with zeros, one with more is cut."""
    readers = {p["attribute"]: p for p in manifest.get("primvars", [])}
    content = []
    for attribute, glsl in manifest.get("attributes", {}).items():
        if not attribute.startswith("i_geomprop_") or attribute not in prog or glsl not in _GLSL_COMPONENTS:
            continue
        reader = readers.get(attribute)
        values = mesh.primvars.get(reader["varname"] if reader else attribute[len("i_geomprop_"):])
        if values is None:
            continue
        k, dtype, code = _GLSL_COMPONENTS[glsl]
        key = (attribute, glsl)
        if key not in cache:
            rows = np.zeros((len(values), k))
            rows[:, :min(k, values.shape[1])] = values[:, :k]
            if code == "i":
                rows = np.clip(np.rint(rows), -2 ** 31, 2 ** 31 - 1)
            cache[key] = (ctx.buffer(np.ascontiguousarray(rows, dtype=dtype).tobytes()), "%d%s" % (k, code))
        buf, fmt = cache[key]
        content.append((buf, fmt, attribute))
    for attribute, reader in readers.items():
        if reader["uniform"] in prog:
            prog[reader["uniform"]].value = int(any(name == attribute for _, _, name in content))
    return content


class _StageCamera:
    """The stage camera's matrices as render.Renderer.bind reads a camera (the aspect is the stage's own)."""

    def __init__(self, eye, view_projection):
        self.eye, self._view_projection = eye, view_projection

    def view_projection(self, aspect=1.0):
        return self._view_projection


