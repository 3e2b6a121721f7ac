"""Meshes for the viewer (`mtlxgen view --geometry`): built-in sphere, plane, cube and a shaderball-like lathe,
or a mesh file read by trimesh. Each is (attributes, index) as render.sphere() returns them: i_position,
i_normal, i_tangent, i_bitangent (float32, n x 3), i_texcoord_0 (n x 2) and a flat int32 triangle index.
Conventions are the sphere's: the bitangent is normal x tangent and points along +v, the tangent along +u.
"""
import os

import numpy as np

from mtlxgen.base.diagnostics import Loc, MtlxError

BUILTIN = ("sphere", "plane", "cube", "shaderball")


def _f4(x):
    return np.ascontiguousarray(x, dtype="f4")


def _mesh(pos, normal, tangent, uv, index):
    normal = normal / np.maximum(np.linalg.norm(normal, axis=-1, keepdims=True), 1e-12)
    return {"i_position": _f4(pos), "i_normal": _f4(normal), "i_tangent": _f4(tangent),
            "i_bitangent": _f4(np.cross(normal, tangent)), "i_texcoord_0": _f4(uv)}, \
        np.ascontiguousarray(index, dtype="i4").reshape(-1)


def _grid_index(rows, cols, first=0):
    """Two triangles per cell of a (rows + 1) x (cols + 1) vertex grid, counter-clockwise seen from the front."""
    i = first + np.arange(rows)[:, None] * (cols + 1) + np.arange(cols)[None, :]
    a, b, c, d = i, i + 1, i + cols + 1, i + cols + 2
    return np.stack([a, b, d, a, d, c], -1).reshape(-1)


def sphere():
    from mtlxgen.draw.renderer import sphere as unit_sphere
    return unit_sphere()


def plane(size=2.0, cells=32):
    """A square of side `size` in the xy plane facing +z (the default camera), uv (0, 0) at its lower left."""
    t = np.linspace(0.0, 1.0, cells + 1)
    u, v = np.meshgrid(t, t)
    pos = np.stack([(u - 0.5) * size, (v - 0.5) * size, np.zeros_like(u)], -1).reshape(-1, 3)
    n = pos.shape[0]
    return _mesh(pos, np.tile([0.0, 0.0, 1.0], (n, 1)), np.tile([1.0, 0.0, 0.0], (n, 1)),
                 np.stack([u, v], -1).reshape(-1, 2), _grid_index(cells, cells))


def cube(size=1.4, cells=8):
    """A cube of side `size` about the origin: six faces of their own (hard edges), each with uv 0..1."""
    # (normal, tangent = +u direction); the face's +v direction is normal x tangent
    faces = [((0, 0, 1), (1, 0, 0)), ((1, 0, 0), (0, 0, -1)), ((0, 0, -1), (-1, 0, 0)), ((-1, 0, 0), (0, 0, 1)),
             ((0, 1, 0), (1, 0, 0)), ((0, -1, 0), (1, 0, 0))]
    t = np.linspace(0.0, 1.0, cells + 1)
    u, v = np.meshgrid(t, t)
    uv = np.stack([u, v], -1).reshape(-1, 2)
    parts = []
    for k, (n, tg) in enumerate(faces):
        n, tg = np.array(n, float), np.array(tg, float)
        bt = np.cross(n, tg)
        pos = (n[None] + (uv[:, :1] - 0.5) * 2 * tg[None] + (uv[:, 1:] - 0.5) * 2 * bt[None]) * (size / 2)
        m = pos.shape[0]
        parts.append((pos, np.tile(n, (m, 1)), np.tile(tg, (m, 1)), uv, _grid_index(cells, cells, k * m)))
    return _mesh(*(np.concatenate([p[i] for p in parts]) for i in range(5)))


def _shaderball_profile():
    """Smooth pieces of the profile (radius, height) from the bottom of the base to the top of the ball; the
    pieces meet at hard edges. A ball of radius 0.95 with a groove round its equator, on a neck and a plate."""
    R = 0.95
    groove_r, groove_h = 0.86, 0.07
    neck_r, plate_r, plate_y, plate_t = 0.3, 0.8, -1.17, 0.1
    neck_top = -np.sqrt(R * R - neck_r * neck_r)

    def line(a, b, n=2):
        return np.linspace(a, b, n)

    def arc(y0, y1, n):
        y = np.linspace(y0, y1, n)
        return np.stack([np.sqrt(np.maximum(R * R - y * y, 0.0)), y], -1)

    return [
        line((0.0, plate_y), (plate_r, plate_y), 8),                                    # underside
        line((plate_r, plate_y), (plate_r, plate_y + plate_t), 3),                      # plate's rim
        line((plate_r, plate_y + plate_t), (neck_r, plate_y + plate_t), 6),             # plate's top
        line((neck_r, plate_y + plate_t), (neck_r, neck_top), 4),                       # neck
        arc(neck_top, -groove_h, 24),                                                   # lower half of the ball
        line((np.sqrt(R * R - groove_h ** 2), -groove_h), (groove_r, -groove_h), 3),    # groove's floor
        line((groove_r, -groove_h), (groove_r, groove_h), 4),                           # groove's wall
        line((groove_r, groove_h), (np.sqrt(R * R - groove_h ** 2), groove_h), 3),      # groove's ceiling
        np.concatenate([arc(groove_h, R * 0.999, 30), [[0.0, R]]]),                     # upper half, to the pole
    ]


def lathe(pieces, segments=96):
    """Revolve profile pieces [(radius, height) rows] about +y: u once around (as the sphere's), v along the
    profile's length from its first point to its last."""
    lengths = [np.linalg.norm(np.diff(p, axis=0), axis=1) for p in pieces]
    total = sum(l.sum() for l in lengths)
    phi = np.linspace(0.0, 2.0 * np.pi, segments + 1)
    out, start, first = [], 0.0, 0
    for p, seg in zip(pieces, lengths):
        v = (start + np.concatenate([[0.0], np.cumsum(seg)])) / total
        start += seg.sum()
        d = np.gradient(p, axis=0) if len(p) > 2 else np.repeat(np.diff(p, axis=0), 2, axis=0)
        n2 = np.stack([d[:, 1], -d[:, 0]], -1)               # outward: the profile's direction turned clockwise
        n2 /= np.maximum(np.linalg.norm(n2, axis=1, keepdims=True), 1e-12)
        ones = np.ones((len(p), segments + 1))
        r, y = p[:, 0][:, None] * ones, p[:, 1][:, None] * ones
        nr, ny = n2[:, 0][:, None] * ones, n2[:, 1][:, None] * ones
        c, s = np.cos(phi)[None] * ones, np.sin(phi)[None] * ones
        pos = np.stack([r * c, y, -r * s], -1)
        nrm = np.stack([nr * c, ny, -nr * s], -1)
        tan = np.stack([-s, 0.0 * ones, -c], -1)
        uu, vv = np.meshgrid(phi / (2.0 * np.pi), v)
        out.append((pos.reshape(-1, 3), nrm.reshape(-1, 3), tan.reshape(-1, 3),
                    np.stack([uu, vv], -1).reshape(-1, 2), _grid_index(len(p) - 1, segments, first)))
        first += len(p) * (segments + 1)
    return _mesh(*(np.concatenate([o[i] for o in out]) for i in range(5)))


def shaderball():
    """A shaderball-like shape made here: a ball with a groove round its equator on a neck and a round plate."""
    return lathe(_shaderball_profile())


def tangents(pos, normal, uv, index):
    """Per-vertex tangents from texture-coordinate gradients (Lengyel's method: each triangle's dP/du
    accumulated at its corners, made orthogonal to the normal); bitangents normal x tangent, turned round
    where the triangle's uv is mirrored. Vertices with no usable uv get any tangent perpendicular to the normal."""
    tri = index.reshape(-1, 3)
    p0, p1, p2 = (pos[tri[:, k]] for k in range(3))
    t0, t1, t2 = (uv[tri[:, k]] for k in range(3))
    e1, e2, d1, d2 = p1 - p0, p2 - p0, t1 - t0, t2 - t0
    det = d1[:, 0] * d2[:, 1] - d2[:, 0] * d1[:, 1]
    ok = np.abs(det) > 1e-20
    r = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)[:, None]
    tu = (e1 * d2[:, 1:2] - e2 * d1[:, 1:2]) * r
    tv = (e2 * d1[:, 0:1] - e1 * d2[:, 0:1]) * r
    T, B = np.zeros_like(pos), np.zeros_like(pos)
    for k in range(3):
        np.add.at(T, tri[:, k], tu)
        np.add.at(B, tri[:, k], tv)
    T = T - normal * (T * normal).sum(-1, keepdims=True)
    bad = np.linalg.norm(T, axis=1) < 1e-12
    if bad.any():        # any direction perpendicular to the normal
        axis = np.where(np.abs(normal[bad, 0:1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
        T[bad] = np.cross(np.cross(normal[bad], axis), normal[bad])
    T /= np.maximum(np.linalg.norm(T, axis=1, keepdims=True), 1e-12)
    bitangent = np.cross(normal, T)
    flip = (bitangent * B).sum(-1) < 0.0
    bitangent[flip] *= -1.0
    return T, bitangent


def load_mesh(path):
    """A mesh file (OBJ, PLY, STL, glTF, OFF ... whatever trimesh reads) as (attributes, index); every mesh of
    a scene concatenated. Normals from the file, else trimesh's smooth vertex normals; uv from the file, else 0."""
    try:
        import trimesh
    except ImportError:
        raise MtlxError((Loc(path, 0), "reading mesh files needs trimesh (pip install 'mtlxgen[view]')")) from None
    if not os.path.isfile(path):
        raise MtlxError((Loc(path, 0), "no such file"))
    try:
        loaded = trimesh.load(path, process=False)
        meshes = (list(loaded.dump()) if isinstance(loaded, trimesh.Scene) else [loaded])
    except Exception as e:
        raise MtlxError((Loc(path, 0), "cannot read the mesh: %s" % (str(e).strip().splitlines() or [type(e).__name__])[0]))
    meshes = [m for m in meshes if isinstance(m, trimesh.Trimesh) and len(m.faces)]
    if not meshes:
        raise MtlxError((Loc(path, 0), "no triangles in the mesh file"))
    parts, first = [], 0
    for m in meshes:
        pos = np.asarray(m.vertices, dtype=float)
        normal = np.asarray(m.vertex_normals, dtype=float)
        uv = getattr(m.visual, "uv", None)
        uv = np.zeros((len(pos), 2)) if uv is None or len(uv) != len(pos) else np.asarray(uv, dtype=float)[:, :2]
        index = np.asarray(m.faces, dtype=np.int64).reshape(-1)
        parts.append((pos, normal, uv, index + first))
        first += len(pos)
    pos, normal, uv, index = (np.concatenate([p[i] for p in parts]) for i in range(4))
    if not np.isfinite(pos).all():
        raise MtlxError((Loc(path, 0), "the mesh has non-finite vertex positions"))
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-12)
    tangent, bitangent = tangents(pos, normal, uv, index)
    return {"i_position": _f4(pos), "i_normal": _f4(normal), "i_tangent": _f4(tangent),
            "i_bitangent": _f4(bitangent), "i_texcoord_0": _f4(uv)}, np.ascontiguousarray(index, dtype="i4")


def geometry(name):
    """A built-in shape by name, or a mesh file."""
    if name in BUILTIN:
        return {"sphere": sphere, "plane": plane, "cube": cube, "shaderball": shaderball}[name]()
    return load_mesh(name)


def bounds(attrs):
    """(centre, radius) of the mesh's bounding box and the sphere about its centre holding every vertex."""
    pos = attrs["i_position"].astype(float)
    centre = (pos.min(0) + pos.max(0)) / 2.0
    return centre, float(np.linalg.norm(pos - centre, axis=1).max())
