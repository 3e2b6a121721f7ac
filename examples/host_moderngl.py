#!/usr/bin/env python3
"""A host app of its own: a MaterialX document drawn on a sphere with plain moderngl, bound from the manifest alone.

    python examples/host_moderngl.py examples/quick_start.mtlx                    # a window (glfw)
    python examples/host_moderngl.py DOC.mtlx --headless --out sphere.png         # no window: a PNG

The document goes through mtlxgen's API (mtlxgen.generate); the environment through mtlxgen.environment. All the
rest is this file's own GL: the mesh, the camera, the textures, and every uniform and attribute it binds, found by
name in the shader's manifest (docs/interface.md). What it draws equals `mtlxgen render` (tests/top/test_api.py).
"""
import argparse
import math
import sys

import moderngl
import numpy as np

import mtlxgen
from mtlxgen.draw.environment import mip_chain, prepare


def sphere(n_lon=128, n_lat=64):
    """A unit UV sphere, y up: the attributes a manifest may ask for, by name, and a triangle index."""
    u, v = np.meshgrid(np.linspace(0, 1, n_lon + 1), np.linspace(0, 1, n_lat + 1))
    phi, theta = 2 * np.pi * u, np.pi * v
    p = np.stack([np.sin(theta) * np.cos(phi), -np.cos(theta), -np.sin(theta) * np.sin(phi)], -1).reshape(-1, 3)
    t = np.stack([-np.sin(phi), 0 * phi, -np.cos(phi)], -1).reshape(-1, 3)
    i = np.arange(n_lat)[:, None] * (n_lon + 1) + np.arange(n_lon)[None, :]
    index = np.stack([i, i + 1, i + n_lon + 2, i, i + n_lon + 2, i + n_lon + 1], -1).reshape(-1)
    attrs = {"i_position": p, "i_normal": p, "i_tangent": t, "i_bitangent": np.cross(p, t),
             "i_texcoord_0": np.stack([u, v], -1).reshape(-1, 2)}
    return {k: a.astype("f4") for k, a in attrs.items()}, index.astype("i4")


def camera(eye=(0.0, 0.0, 3.0), fov_y=45.0, near=0.1, far=100.0):
    """View-projection (column-vector convention) of a camera at `eye` looking at the origin, square aspect."""
    f = 1.0 / math.tan(math.radians(fov_y) / 2)
    proj = np.array([[f, 0, 0, 0], [0, f, 0, 0], [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)],
                     [0, 0, -1, 0]])
    view = np.eye(4)
    view[:3, 3] = -np.asarray(eye)          # looking down -z from (0, 0, 3): a translation
    return proj @ view, eye


def texture(ctx, levels, mipmaps, sampling=None):
    """A float texture of a mip chain (rows as given). sampling: a manifest texture entry (address modes, filter;
    moderngl's Texture has no mirrored repeat: "mirror" repeats)."""
    h, w, c = levels[0].shape
    t = ctx.texture((w, h), c, np.ascontiguousarray(levels[0], "f4"), dtype="f4")
    if mipmaps:
        t.build_mipmaps()                  # allocates every level; ours go in where we have them
        for k, level in enumerate(levels[1:], 1):
            t.write(np.ascontiguousarray(level, "f4"), level=k)
        t.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
    sampling = sampling or {}
    t.repeat_x, t.repeat_y = (sampling.get(k, "periodic") != "clamp" for k in ("uaddressmode", "vaddressmode"))
    if sampling.get("filtertype") == "closest":
        t.filter = (moderngl.NEAREST, moderngl.NEAREST)
    return t


def image_levels(path, default):
    """An image file's pixels bottom row first (uv (0, 0) is its lower-left corner), or its default colour."""
    try:
        import OpenImageIO as oiio
        oiio.attribute("oiio:UnassociatedAlpha", 1)
        img = oiio.ImageBuf(path).get_pixels(oiio.FLOAT) if path else None
    except Exception:
        img = None
    if img is None or img.size == 0:
        v = list(default if isinstance(default, list) else [default or 0.0] * 3)
        return [np.array((v + [1.0])[:4] if len(v) != 2 else v, "f4").reshape(1, 1, -1)], False
    return [img[::-1]], True


def draw(ctx, shader, size, env_file=None):
    m, prog = shader.manifest, ctx.program(vertex_shader=shader.vertex, fragment_shader=shader.fragment)
    env = prepare(env_file)                       # u_envRadiance's mip chain, u_envIrradiance, their uniforms
    units = {"u_envRadiance": texture(ctx, env.radiance, True), "u_envIrradiance": texture(ctx, [env.irradiance], False)}
    for tex in m["textures"]:                     # each texture the manifest lists, on a unit of its own
        levels, mips = image_levels(tex.get("file"), tex.get("default"))
        levels = mip_chain(levels[0]) if mips else levels
        units[tex["uniform"]] = texture(ctx, levels, mips, tex)
    view_projection, eye = camera()
    values = {u["name"]: u["value"] for u in m["uniforms"]}            # the material's inputs
    values.update({a["name"]: a["default"] for a in m["application"] if a["default"] is not None})
    values.update(env.uniforms)
    values.update({"u_viewProjectionMatrix": view_projection.T.ravel().tolist(), "u_viewPosition": list(eye)})
    for unit, (name, t) in enumerate(units.items()):
        t.use(unit)
        values[name] = unit
    for name, value in values.items():
        if name in prog and not isinstance(value, (dict, type(None))):
            prog[name].value = tuple(value) if isinstance(value, list) and not isinstance(value[0], list) else value
    mesh, index = sphere()
    content = [(ctx.buffer(mesh[a].tobytes()), "%df" % mesh[a].shape[1], a) for a in m["attributes"] if a in prog]
    vao = ctx.vertex_array(prog, content, ctx.buffer(index.tobytes()))
    fbo = ctx.framebuffer([ctx.texture((size, size), 4, dtype="f4")], ctx.depth_renderbuffer((size, size)))
    fbo.use()
    ctx.enable(moderngl.DEPTH_TEST)
    ctx.clear(0.0, 0.0, 0.0, 0.0)
    vao.render()
    return np.frombuffer(fbo.read(components=4, dtype="f4"), "f4").reshape(size, size, 4)[::-1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("document")
    ap.add_argument("--element", help="which element (default: the first)")
    ap.add_argument("--env", help="lat-long HDR/EXR environment (default: mtlxgen's sky)")
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--headless", action="store_true", help="no window: draw once into --out")
    ap.add_argument("--out", default="host.png", help="headless: the picture (.png sRGB, .exr/.npy linear)")
    args = ap.parse_args()
    try:
        shader = mtlxgen.generate(args.document, args.element)[0]
    except mtlxgen.DocumentError as e:
        sys.exit(str(e))
    if args.headless:
        ctx = moderngl.create_standalone_context(require=400, backend="egl")
        img = draw(ctx, shader, args.size, args.env)
        if args.out.endswith(".npy"):
            np.save(args.out, img)
        else:
            from mtlxgen.base.images import write_image
            write_image(args.out, img)
        return
    import glfw
    glfw.init()
    for hint, value in ((glfw.CONTEXT_VERSION_MAJOR, 4), (glfw.CONTEXT_VERSION_MINOR, 1),
                        (glfw.OPENGL_PROFILE, glfw.OPENGL_CORE_PROFILE), (glfw.OPENGL_FORWARD_COMPAT, True)):
        glfw.window_hint(hint, value)
    window = glfw.create_window(args.size, args.size, shader.name, None, None)
    glfw.make_context_current(window)
    ctx = moderngl.create_context()
    img = draw(ctx, shader, args.size, args.env)            # drawn once (the scene does not move), linear
    from mtlxgen.base.images import to_srgb8
    shown = ctx.framebuffer([ctx.texture((args.size, args.size), 4, to_srgb8(img)[::-1].tobytes())])
    while not glfw.window_should_close(window):
        ctx.copy_framebuffer(ctx.screen, shown)
        glfw.swap_buffers(window)
        glfw.wait_events()
    glfw.terminate()


if __name__ == "__main__":
    main()
