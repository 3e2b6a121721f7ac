"""Headless render harness: a sphere lit by a lat-long environment, drawn with moderngl.

Scene (fixed, deterministic): unit sphere at the origin with positions, normals, tangents,
bitangents and texcoords; camera at (0, 0, 3) looking at the origin, 45 degree vertical fov; a
built-in HDR sky (or any HDR/EXR file) bound as u_envRadiance with a full mip chain and its
irradiance (order-2 spherical harmonics, projected with numpy a band of rows at a time) as u_envIrradiance.
Rendering is into a float framebuffer; the result is linear RGBA with row 0 at the top.

Texture and environment files are read through images.read_image: at most 4 channels, as 32-bit floats of at
most images.MAX_DECODED_BYTES (a larger image, such as a 16384 x 8192 map, is box-filtered down by a power of
two as it is read) and handed to GL without another copy. A texture file that is missing draws the sampler's
default; one that is there but cannot be bound (not a regular file, not an image, damaged) is an error.
"""
import os
import sys
import time
from mtlxgen.base.records import dataclass
from typing import Callable, Optional

import numpy as np

from mtlxgen.base.diagnostics import Loc, MtlxError
# the environment recipe (mip chain, SH irradiance, the lat-long frame ENV_MATRIX, the sample count) is environment.py's,
# shared with view, web, three and any host; these names stay here for render's callers
from mtlxgen.draw.environment import (ENV_MATRIX, ENV_SAMPLES, _latlong_directions, _sh9, builtin_sky,  # noqa: F401
                                      irradiance_map, load_environment, mip_count, sh9_projection)
from mtlxgen.base.files import check_regular
from mtlxgen.draw.glcontext import create_context  # noqa: F401  (render.create_context for callers)
from mtlxgen.base.images import read_image, write_image  # noqa: F401  (re-exported for the CLI)

SIZE = 256
EYE = (0.0, 0.0, 3.0)
FOV_Y = 45.0


def sphere(n_lon=128, n_lat=64):
    """Unit UV sphere, y up. u runs once around the equator, v from the bottom pole (0) to the top (1)."""
    u = np.linspace(0.0, 1.0, n_lon + 1)
    v = np.linspace(0.0, 1.0, n_lat + 1)
    uu, vv = np.meshgrid(u, v)
    phi = uu * 2.0 * np.pi
    theta = vv * np.pi
    sin_t = np.sin(theta)
    pos = np.stack([sin_t * np.cos(phi), -np.cos(theta), -sin_t * np.sin(phi)], -1).reshape(-1, 3)
    tangent = np.stack([-np.sin(phi), np.zeros_like(phi), -np.cos(phi)], -1).reshape(-1, 3)
    bitangent = np.cross(pos, tangent)
    uv = np.stack([uu, vv], -1).reshape(-1, 2)
    i = np.arange(n_lat)[:, None] * (n_lon + 1) + np.arange(n_lon)[None, :]
    a, b, c, d = i, i + 1, i + n_lon + 1, i + n_lon + 2
    index = np.stack([a, b, d, a, d, c], -1).reshape(-1).astype("i4")
    f4 = lambda x: np.ascontiguousarray(x, dtype="f4")
    return {"i_position": f4(pos), "i_normal": f4(pos), "i_tangent": f4(tangent),
            "i_bitangent": f4(bitangent), "i_texcoord_0": f4(uv)}, index


def perspective(fov_y, aspect, near, far):
    f = 1.0 / np.tan(np.radians(fov_y) / 2.0)
    m = np.zeros((4, 4))
    m[0, 0], m[1, 1] = f / aspect, f
    m[2, 2], m[2, 3] = (far + near) / (near - far), 2.0 * far * near / (near - far)
    m[3, 2] = -1.0
    return m


def look_at(eye, target, up):
    eye, target, up = (np.asarray(x, dtype=float) for x in (eye, target, up))
    fwd = target - eye
    fwd /= np.linalg.norm(fwd)
    side = np.cross(fwd, up)
    side /= np.linalg.norm(side)
    m = np.eye(4)
    m[0, :3], m[1, :3], m[2, :3] = side, np.cross(side, fwd), -fwd
    m[:3, 3] = -m[:3, :3] @ eye
    return m


@dataclass(frozen=True)
class Camera:
    """A perspective camera looking from `eye` at `target`; `render`'s is the default (EYE, the origin, FOV_Y)."""
    eye: tuple = EYE
    target: tuple = (0.0, 0.0, 0.0)
    up: tuple = (0.0, 1.0, 0.0)
    fov_y: float = FOV_Y            # vertical field of view, degrees
    near: float = 0.1
    far: float = 100.0

    def view(self):
        return look_at(self.eye, self.target, self.up)

    def projection(self, aspect=1.0):
        return perspective(self.fov_y, aspect, self.near, self.far)

    def view_projection(self, aspect=1.0):
        return self.projection(aspect) @ self.view()


DEFAULT_CAMERA = Camera()


def scoreboard_sky(width=512, height=256):
    """The scoreboard's sky (../shared/tools/mxharness.py's scene), row 0 = top. Its map frame is longitude
    2 pi u measured from +x towards +z, latitude pi (0.5 - v). Above the horizon a blue (0.35, 0.55, 1) scaled
    from 0.4 at the horizon to 1 at the zenith; below it a flat brown (0.25, 0.2, 0.15); a sun of 12 degrees
    radius towards (0.5, 0.6, 0.62) adds 8 (1, 0.95, 0.85) times the square of a ramp that is 0 at its rim
    and 1 at its centre."""
    lon = 2.0 * np.pi * (np.arange(width) + 0.5) / width
    lat = np.pi * (0.5 - (np.arange(height) + 0.5) / height)
    lon, lat = np.meshgrid(lon, lat)
    d = np.stack([np.cos(lat) * np.cos(lon), np.sin(lat), np.cos(lat) * np.sin(lon)], -1)
    height_up = d[..., 1:2]
    blue = np.array([0.35, 0.55, 1.0]) * (0.4 + 0.6 * np.clip(height_up, 0.0, 1.0))
    img = np.where(height_up > 0.0, blue, np.array([0.25, 0.2, 0.15]))
    sun = np.array([0.5, 0.6, 0.62]) / np.linalg.norm([0.5, 0.6, 0.62])
    rim = np.cos(np.radians(12.0))
    ramp = np.clip(((d * sun).sum(-1, keepdims=True) - rim) / (1.0 - rim), 0.0, 1.0)
    return (img + 8.0 * ramp ** 2 * np.array([1.0, 0.95, 0.85])).astype(np.float32)




@dataclass(frozen=True)
class Scene:
    """What a Renderer binds around a shader besides the sphere and camera (which never change). The defaults
    are mtlxgen's scene; SCOREBOARD_SCENE is the scoreboard's, so parity is measured where it is scored."""
    sky: Callable = builtin_sky                 # the lat-long radiance when no environment is given
    sh_irradiance: bool = True                  # u_envIrradiance: the SH irradiance map, or else the radiance map
    env_matrix: Optional[tuple] = ENV_MATRIX    # None leaves the shader's own default
    world_inverse: bool = True                  # False leaves u_worldInverseMatrix unset (all zeros)
    associated_alpha: bool = False              # textures as OpenImageIO reads them by default: rgb times alpha
    ies_profiles: bool = True                   # .ies files bound as measured_edf's profile; False: unreadable


# ../shared/tools/mxharness.py: its sky bound as both radiance and irradiance, only the world, view-projection
# and inverse-transpose matrices written, every texture file read by OpenImageIO's defaults
SCOREBOARD_SCENE = Scene(sky=scoreboard_sky, sh_irradiance=False, env_matrix=None, world_inverse=False,
                         associated_alpha=True, ies_profiles=False)


def _flip_rows(img, chunk=256):
    """Reverse the rows of an array in place, `chunk` rows at a time (img[::-1] would copy all of it)."""
    h = img.shape[0]
    for i in range(0, h // 2, chunk):
        j = min(i + chunk, h // 2)
        top = img[i:j].copy()
        img[i:j] = img[h - j:h - i][::-1]
        img[h - j:h - i] = top[::-1]
    return img


_SAMPLER_TYPES = {0x8B5D, 0x8B5E, 0x8B5F, 0x8B60}      # GL_SAMPLER_1D, _2D, _3D, _CUBE


class UniformBlock:
    """The std140 uniform block of a vulkan-target shader, filled from the manifest's offsets (what a Vulkan
    renderer does with the same manifest) and bound at the block's binding. Names are a member's
    (`u_worldMatrix`) or an array element's field (`u_lightData[2].color`)."""

    def __init__(self, ctx, prog, spec):
        self.spec = spec
        self.members = {m["name"]: m for m in spec["members"]}
        self.data = bytearray(spec["size"])
        self.buffer = ctx.buffer(reserve=max(spec["size"], 16))
        self.binding = spec["binding"]
        if spec["name"] in prog:
            prog[spec["name"]].binding = self.binding

    def locate(self, name):
        """(offset, GLSL type) of a member or member field, None when the block has no such name."""
        base, _, field_ = name.partition(".")
        base, _, index = base.partition("[")
        m = self.members.get(base)
        if m is None:
            return None
        offset, t = m["offset"], m["type"].split("[")[0]
        if index:
            offset += int(index.rstrip("]")) * m.get("stride", 0)
        if field_:
            f = next((f for f in m.get("members", ()) if f["name"] == field_), None)
            if f is None:
                return None
            return offset + f["offset"], f["type"]
        return offset, (m["type"] if not index else t)

    def has(self, name):
        return self.locate(name) is not None

    def set(self, name, value):
        offset, t = self.locate(name)
        m = self.members.get(name)
        if m is not None and m.get("members") and "[" not in t:          # a struct member: values in member order
            for f, v in zip(m["members"], value):
                self.data[offset + f["offset"]:offset + f["offset"] + len(_std140_bytes(f["type"], v))] = \
                    _std140_bytes(f["type"], v)
            return
        raw = _std140_bytes(t, value, m.get("stride", 16) if m is not None else 16)
        self.data[offset:offset + len(raw)] = raw

    def upload(self):
        self.buffer.write(bytes(self.data))
        self.buffer.bind_to_uniform_block(self.binding)

    def release(self):
        self.buffer.release()


_COMPONENTS = {"float": ("f", 1), "int": ("i", 1), "bool": ("i", 1), "uint": ("I", 1), "vec2": ("f", 2),
               "vec3": ("f", 3), "vec4": ("f", 4), "ivec2": ("i", 2), "ivec3": ("i", 3), "ivec4": ("i", 4)}


def _std140_bytes(glsl_type, value, stride=16):
    """A value's bytes as std140 lays it out (targets.std140): matrices column by column, each column padded to
    16 bytes; arrays (`float[3]`) element by element at `stride`. Matrices come as column-major numbers or as
    the column-major float32 bytes moderngl's write() takes."""
    import struct
    base, _, length = glsl_type.partition("[")
    if length:
        out = bytearray(stride * int(length.rstrip("]")))
        for i, v in enumerate(value):
            raw = _std140_bytes(base, v)
            out[i * stride:i * stride + len(raw)] = raw
        return bytes(out)
    if base in ("mat2", "mat3", "mat4"):
        n = int(base[3])
        flat = (np.frombuffer(value, dtype="f4") if isinstance(value, (bytes, bytearray))
                else np.asarray(value, dtype="f4").reshape(-1))
        cols = np.zeros((n, 4), dtype="f4")
        cols[:, :n] = flat.reshape(n, n)
        return cols.tobytes()
    code, n = _COMPONENTS[base]
    values = [value] if n == 1 and not isinstance(value, (list, tuple)) else list(value)
    values = [int(v) for v in values] if code in "iI" else [float(v) for v in values]
    return struct.pack("<%d%s" % (n, code), *values)


class Prepared:
    """A linked shader ready to draw (Renderer.prepare): its program, the geometry's vertex array, and the
    samplers' files and default colours. Textures are looked up in the renderer's cache at each draw, so a
    file dropped from it (Renderer.forget_texture) is read again by the next draw. Release when done.

    set() gives a uniform its value whatever the target declared it as: a plain uniform, or a member of a
    vulkan shader's uniform block (uploaded by the draw)."""

    def __init__(self, prog, vao, samplers, manifest, block=None):
        self.prog = prog
        self.vao = vao
        self.samplers = samplers        # [(uniform, file or None, default colour or None)], sorted by uniform
        self.manifest = manifest or {}
        self.block = block              # UniformBlock of a vulkan-target shader, else None

    def has(self, name):
        return name in self.prog or (self.block is not None and self.block.has(name))

    def set(self, name, value):
        """Set a uniform (False where the shader does not have it). Matrices as column-major float32 bytes."""
        if self.block is not None and self.block.has(name):
            self.block.set(name, value)
            return True
        if name not in self.prog:
            return False
        u = self.prog[name]
        if isinstance(value, (bytes, bytearray)):
            u.write(value)
        else:
            u.value = int(value) if isinstance(value, bool) else value
        return True

    def set_defaults(self):
        """The values a target without initializers (essl, vulkan) leaves to the application: the application
        uniforms' defaults and the material's values, from the manifest."""
        for entry in self.manifest.get("application", ()):
            if entry.get("default") is not None:
                value = entry["default"]
                if entry["type"].startswith("mat"):
                    value = np.asarray(value, dtype="f4").tobytes()
                self.set(entry["name"], value)
        for entry in self.manifest.get("uniforms", ()):
            self.set_material(entry)

    def set_material(self, entry):
        value = entry["value"]
        if value is None:
            return
        if entry.get("members") and not (self.block is not None and self.block.has(entry["name"])):
            for f, v in zip(entry["members"], value):        # a struct uniform: one uniform per member
                self.set("%s.%s" % (entry["name"], f["name"]), v)
            return
        t = entry["type"]
        if t.startswith("mat"):
            value = np.asarray(value, dtype="f4").tobytes()
        elif "[" in t and isinstance(value, (list, tuple)) and value and isinstance(value[0], (list, tuple)):
            value = [tuple(v) for v in value]
        elif isinstance(value, list):
            value = tuple(value)
        self.set(entry["name"], value)

    def upload(self):
        if self.block is not None:
            self.block.upload()

    def release(self):
        if self.vao is not None:
            self.vao.release()
        if self.block is not None:
            self.block.release()
        self.prog.release()
        self.vao = None


class Renderer:
    """One GL context, one mesh (the sphere unless told), one environment; renders Shader objects (or
    vertex/fragment pairs). render() draws into its own size x size float framebuffer from `render`'s camera;
    prepare() + draw() draw into any framebuffer (a window's) from any Camera: the same binding code."""

    @classmethod
    def scoreboard(cls, size=SIZE):
        """A Renderer that draws what the scoreboard's harness draws (SCOREBOARD_SCENE)."""
        return cls(size=size, scene=SCOREBOARD_SCENE)

    def __init__(self, size=SIZE, environment=None, env_samples=ENV_SAMPLES, lights=(), scene=Scene(), ctx=None,
                 geometry=None):
        """ctx: a moderngl context to draw with (a window's), left open by close(); None: a headless one of
        its own. geometry: (attributes, index) as sphere() returns them; None: the sphere."""
        import moderngl
        self.mgl = moderngl
        self._owns_ctx = ctx is None
        self.ctx = create_context() if ctx is None else ctx
        self.size = size
        self.env_samples = env_samples
        self.scene = scene
        self.lights = list(lights)      # LightData records (lights.load_light_rig) bound to u_lightData[]
        self.fbo = self.ctx.framebuffer(color_attachments=[self.ctx.texture((size, size), 4, dtype="f4")],
                                        depth_attachment=self.ctx.depth_renderbuffer((size, size)))
        self.buffers, self.index = {}, None
        self.set_geometry(*(geometry or sphere()))
        self._image_cache = {}
        self.set_environment(environment)

    def set_geometry(self, attrs, index):
        """Draw this mesh from now on: attributes {i_position: (n, 3) float32, ...} and a flat int32 index."""
        old = list(self.buffers.values()), self.index
        self.buffers = {k: (self.ctx.buffer(np.ascontiguousarray(v, dtype="f4").tobytes()), "%df" % v.shape[1])
                        for k, v in attrs.items()}
        self.index = self.ctx.buffer(np.ascontiguousarray(index, dtype="i4").tobytes())
        for buf, _ in old[0]:
            buf.release()
        if old[1] is not None:
            old[1].release()

    def set_environment(self, environment=None):
        """Light with this lat-long radiance map (None: the scene's sky) and its irradiance. The GGX-prefiltered map
        that shaders of the prefiltered method read (prefiltered_env) is made from it when one is first drawn."""
        for t in {id(t): t for t in (getattr(self, "env", None), getattr(self, "irradiance", None),
                                     getattr(self, "_prefiltered", None)) if t}.values():
            t.release()
        self._prefiltered = None
        env = self.scene.sky() if environment is None else np.asarray(environment, dtype=np.float32)
        # lat-long maps go up top row first: v = 0 is the top of the image (interface.md)
        self.env = self._float_texture(env, mipmaps=True, top_first=True)
        self.env_mips = mip_count(env.shape[1], env.shape[0])
        self.irradiance = (self._float_texture(irradiance_map(env), mipmaps=False, top_first=True)
                           if self.scene.sh_irradiance else self.env)

    def prefiltered_env(self):
        """The GGX-prefiltered radiance map of this environment (environment.Prefilter: made on the GPU at the first
        call, kept until the environment changes), bound as u_envRadiance to shaders whose manifest says
        "environment": "prefiltered"."""
        if self._prefiltered is None:
            from mtlxgen.draw.environment import Prefilter
            pass_ = Prefilter(self.ctx)
            try:
                self._prefiltered = pass_.run(self.env)
            finally:
                pass_.release()
        return self._prefiltered

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self):
        if self.ctx is not None:
            if not self._owns_ctx:          # a window's context: release what was made in it, leave it open
                for t in ([self.fbo, self.fbo.depth_attachment, self.index, self.env] + list(self.fbo.color_attachments)
                          + [b for b, _ in self.buffers.values()] + self._textures()
                          + ([self._prefiltered] if self._prefiltered is not None else [])):
                    t.release()
                if self.irradiance is not self.env:
                    self.irradiance.release()
                self._image_cache = {}
                self.ctx = None
                return
            loader = (self.ctx.extra or {}).get("osmesa") if isinstance(self.ctx.extra, dict) else None
            self.ctx.release()
            if loader is not None:
                loader.release()
            self.ctx = None

    def _float_texture(self, img, mipmaps, top_first=False):
        """Image textures go up bottom row first (uv (0, 0) = lower-left corner); lat-long maps top first."""
        return self._texture_of([np.ascontiguousarray(img if top_first else img[::-1], dtype="f4")], mipmaps)

    def _texture_of(self, held, mipmaps):
        """A float texture of the one contiguous float32 array in `held`, rows as they are. GL reads the array's
        own memory (no bytes copy); `held` is emptied once GL has its copy, so that where the caller kept no other
        reference the array is freed before the mip chain is built (Mesa builds it beside a copy of level 0)."""
        img = held.pop()
        t = self.ctx.texture((img.shape[1], img.shape[0]), img.shape[2], memoryview(img), dtype="f4")
        del img
        if mipmaps:
            t.build_mipmaps()
            t.filter = (self.mgl.LINEAR_MIPMAP_LINEAR, self.mgl.LINEAR)
        else:
            t.filter = (self.mgl.LINEAR, self.mgl.LINEAR)
        return t

    def image_texture(self, path):
        """The texture of an image file a sampler names; None where there is no such file (its default is drawn).
        A file that is there but cannot be bound (not a regular file, over a size cap, not an image, damaged
        pixels) is an error: MtlxError, one line naming it, raised again at every later bind."""
        if path not in self._image_cache:
            try:
                self._image_cache[path] = self._load_texture(path)
            except MtlxError as e:
                self._image_cache[path] = e
        t = self._image_cache[path]
        if isinstance(t, MtlxError):
            raise MtlxError(t.problems)
        return t

    def _load_texture(self, path):
        if not os.path.lexists(path):
            return None
        if path.lower().endswith(".ies"):
            if not self.scene.ies_profiles:     # the scoreboard's harness has no IES reader: its default is drawn
                check_regular(path, Loc(path, 0), "image file")
                return None
            from mtlxgen.draw.ies import load_texture       # measured_edf's profile (ies.py)
            return self._float_texture(load_texture(path), mipmaps=False, top_first=True)
        # decoded band by band into at most images.MAX_DECODED_BYTES (a larger image is box-filtered down as it
        # is read), turned bottom row first in place, and handed to GL without a copy
        held = [read_image(path, reduce=True, associated=self.scene.associated_alpha)]
        _flip_rows(held[0])
        return self._texture_of(held, mipmaps=True)

    def _textures(self):
        """The GL textures of the image cache (not its files' absences or errors)."""
        return [t for t in self._image_cache.values() if t is not None and not isinstance(t, MtlxError)]

    def forget_texture(self, path):
        """Drop a file's texture (it changed on disk): the next draw that binds it reads it again."""
        t = self._image_cache.pop(path, None)
        if t is not None and not isinstance(t, MtlxError):
            t.release()

    def trim_images(self, keep):
        """Forget the oldest textures of image files (and constants) beyond `keep`: read again when bound again, the
        same pixels. Between drawings only (batch, after each job): a process that draws a whole library holds a
        bounded set."""
        for path in list(self._image_cache)[:max(0, len(self._image_cache) - keep)]:
            self.forget_texture(path)

    def constant_texture(self, value):
        """A 1x1 texture of an image node's `default` (what a viewer binds when the file cannot be read)."""
        v = [float(x) for x in (value if isinstance(value, (list, tuple)) else [value])]
        rgba = {1: v * 3 + [1.0], 2: v + [0.0, 1.0], 3: v + [1.0]}.get(len(v), v[:4])
        key = ("constant",) + tuple(rgba)
        if key not in self._image_cache:
            self._image_cache[key] = self._float_texture(np.array(rgba, dtype="f4").reshape(1, 1, 4), mipmaps=False)
        return self._image_cache[key]

    def render(self, shader, textures=None):
        """Render a Shader (or a (vertex, fragment) pair). Returns linear RGBA float32, row 0 on top."""
        if isinstance(shader, tuple):
            vertex, fragment, manifest = shader[0], shader[1], {}
        else:
            vertex, fragment, manifest = shader.vertex, shader.fragment, shader.manifest
        img, _ = self.render_timed(vertex, fragment, manifest, textures)
        return img

    def render_timed(self, vertex, fragment, manifest=None, textures=None):
        if self._owns_ctx:
            self.ctx.__enter__()    # make this renderer's context current: another Renderer may have been used since
        t0 = time.perf_counter()
        prepared = self.prepare(vertex, fragment, manifest, textures, vertex_array=False)
        t1 = time.perf_counter()
        try:
            self.draw(prepared)
            raw = self.fbo.read(components=4, dtype="f4")
            t2 = time.perf_counter()
        finally:
            prepared.release()
        img = np.frombuffer(raw, dtype="f4").reshape(self.size, self.size, 4)[::-1].copy()
        return img, {"link_s": t1 - t0, "draw_s": t2 - t1}

    def prepare(self, vertex, fragment, manifest=None, textures=None, vertex_array=True):
        """Link a shader for drawing (Prepared). textures: {sampler uniform: file} over the manifest's.
        vertex_array=False leaves the vertex array to the first draw (render_timed times linking alone)."""
        from mtlxgen.base.targets import for_opengl
        manifest = manifest or {}
        prog = self.ctx.program(vertex_shader=for_opengl(vertex), fragment_shader=for_opengl(fragment))
        block = UniformBlock(self.ctx, prog, manifest["uniform_block"]) if manifest.get("uniform_block") else None
        bound, defaults = {}, {}
        for tex in (manifest or {}).get("textures", []):
            bound[tex["uniform"]] = tex.get("file")
            defaults[tex["uniform"]] = tex.get("default")
        bound.update(textures or {})
        samplers = [(name, path, defaults.get(name)) for name, path in sorted(bound.items())]
        prepared = Prepared(prog, None, samplers, manifest, block)
        if manifest.get("target", "glsl") != "glsl":     # no initializers: the manifest's values
            prepared.set_defaults()
        if vertex_array:
            prepared.vao = self._vertex_array(prog)
        return prepared

    def _vertex_array(self, prog):
        content = [(buf, fmt, name) for name, (buf, fmt) in self.buffers.items() if name in prog]
        return self.ctx.vertex_array(prog, content, self.index)

    def bind(self, prepared, camera=None, aspect=1.0, world=None, env_samples=None, sample_frame=(0, 1),
             lights=None):
        """Set everything a shader reads besides its own inputs: textures on units, the matrices of `camera`
        (render's when None) at this aspect, the environment, its sample count (the renderer's when None) and
        progressive frame (frame k of K: u_envSampleFrame, u_envSampleFrames; (0, 1) is the plain estimate),
        and the lights (the renderer's when None; () for none)."""
        prog = prepared.prog
        camera = camera or DEFAULT_CAMERA
        radiance = self.prefiltered_env() if prepared.manifest.get("environment") == "prefiltered" else self.env
        units = [("u_envRadiance", radiance), ("u_envIrradiance", self.irradiance)]
        for name, path, default in prepared.samplers:
            t = self.image_texture(path) if path else None
            if t is None and default is not None:     # unreadable file: its default colour
                t = self.constant_texture(default)
            if t is not None:
                units.append((name, t))
        for unit, (name, t) in enumerate(units):
            if name in prog:
                t.use(unit)
                prog[name].value = unit
        # a sampler left without a texture (a file that could not be read, without a default) reads a
        # transparent black texel on a unit of its own, not whatever an earlier draw left on unit 0
        unbound = [n for n in prog if n not in dict(units) and getattr(prog[n], "gl_type", None) in _SAMPLER_TYPES]
        if unbound:
            empty = self.constant_texture([0.0, 0.0, 0.0, 0.0])
            empty.use(len(units))
            for name in unbound:
                prog[name].value = len(units)
        view_proj = camera.view_projection(aspect)
        world = np.eye(4) if world is None else np.asarray(world, dtype=float)
        mats = {"u_worldMatrix": world, "u_viewProjectionMatrix": view_proj,
                "u_worldInverseTransposeMatrix": np.linalg.inv(world).T}
        if self.scene.world_inverse:
            mats["u_worldInverseMatrix"] = np.linalg.inv(world)
        if self.scene.env_matrix is not None:
            mats["u_envMatrix"] = np.array(self.scene.env_matrix)
        for name, m in mats.items():
            prepared.set(name, np.ascontiguousarray(m.T, dtype="f4").tobytes())
        from mtlxgen.base.interface import TABLE        # the application interface: what is bound here, and the defaults
        if int(sample_frame[1]) > 1:
            application = {a.get("name") for a in (prepared.manifest or {}).get("application", ())}
            if "u_envRadiance" in application and "u_envSampleFrames" not in application:
                raise MtlxError((Loc(prepared.manifest.get("element", "shader"), 0),
                                 "generated without progressive refinement (a reduced shader reads one frame): "
                                 "generate it with --keep u_envSampleFrames to draw frame %d of %d"
                                 % (int(sample_frame[0]), int(sample_frame[1]))))
        scalars = {"u_viewPosition": tuple(float(x) for x in camera.eye), "u_envRadianceMips": self.env_mips,
                   "u_envRadianceSamples": self.env_samples if env_samples is None else env_samples,
                   "u_envLightIntensity": TABLE["u_envLightIntensity"].default,
                   "u_numActiveLightSources": TABLE["u_numActiveLightSources"].default,
                   "u_envSampleFrame": int(sample_frame[0]), "u_envSampleFrames": int(sample_frame[1])}
        for name, value in scalars.items():
            prepared.set(name, value)
        lights = self.lights if lights is None else lights
        if lights and prepared.manifest.get("max_lights", len(lights)) < len(lights):
            raise MtlxError((Loc(prepared.manifest.get("element", "shader"), 0),
                             "generated for %d direct lights, %d bound: generate it with max_lights=%d "
                             "(--max-lights, or render --lights RIG)" % (prepared.manifest["max_lights"], len(lights),
                                                                         len(lights))))
        if lights:
            from mtlxgen.draw.lights import bind_lights
            bind_lights(prepared, lights)
        prepared.upload()

    def draw(self, prepared, target=None, camera=None, clear=True, **binding):
        """Draw a Prepared shader into `target` (a framebuffer; this renderer's own when None) from `camera`,
        at the target's aspect; `binding` as bind() takes it. clear: clear colour and depth first."""
        ctx = self.ctx
        target = self.fbo if target is None else target
        if prepared.vao is None:
            prepared.vao = self._vertex_array(prepared.prog)
        width, height = target.size
        self.bind(prepared, camera, width / float(height), **binding)
        target.use()
        ctx.enable(self.mgl.DEPTH_TEST)
        if clear:
            ctx.clear(0.0, 0.0, 0.0, 0.0)
        prepared.vao.render()


# mtlxgen.render(shader_or_source, ...): this module, callable as the public API's render (mtlxgen/__init__.py)
