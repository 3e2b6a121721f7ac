"""The environment a host binds: a lat-long HDR map as u_envRadiance (with its full mip chain) and
u_envIrradiance, and the values of the uniforms that go with them (docs/interface.md, "The environment").

The one recipe `render`, `view`, `web` and `three` light with, for any OpenGL host:

    env = mtlxgen.draw.environment.prepare("studio.exr")      # or None: render's built-in sky
    env.radiance          # [level 0, 1, ..., 1x1]: (h, w, 3) float32 arrays, row 0 = the map's top
    env.irradiance        # (64, 128, 3) float32: irradiance / pi from the map's order-2 spherical harmonics
    env.uniforms          # {"u_envRadianceMips": ..., "u_envRadianceSamples": ..., "u_envMatrix": [16 floats,
                          #  column-major], "u_envLightIntensity": ...}: set these as they are

Upload every level as it is (top row first: the lat-long lookup's v = 0 is row 0), linear-mipmap-linear
filtering for the radiance, linear for the irradiance, wrap repeat. A host that builds the chain itself
(glGenerateMipmap) binds the same picture: mip_chain is what Mesa's generator makes, a 2x2 box for even sizes.
Plain numpy: nothing here needs a GL context.
"""
from mtlxgen.base.records import dataclass, field

import numpy as np

# the prefilter's recipe is part of the shaders' application interface, which interface.py holds (the manifest
# writes it); PREFILTER_RECIPE is re-exported here for hosts
from mtlxgen.base.interface import PREFILTER_LIB, PREFILTER_RECIPE, PREFILTER_SAMPLES, PREFILTER_TEXELS  # noqa: F401

ENV_SAMPLES = 64        # u_envRadianceSamples render, view's converged picture, web and three bind
IRRADIANCE_SIZE = (128, 64)

# the lat-long frame of interface.md: x and z negated (the same as the shaders' default u_envMatrix), row-major
ENV_MATRIX = ((-1.0, 0.0, 0.0, 0.0), (0.0, 1.0, 0.0, 0.0), (0.0, 0.0, -1.0, 0.0), (0.0, 0.0, 0.0, 1.0))


def mip_count(width, height):
    """u_envRadianceMips: the levels of a full mip chain, floor(log2(max(w, h))) + 1."""
    return int(np.floor(np.log2(max(int(width), int(height))))) + 1


def builtin_sky(width=512, height=256):
    """Deterministic HDR lat-long sky (row 0 = top): horizon-to-zenith blue, warm ground, a sun disc."""
    # direction per the lat-long convention of interface.md: u = atan(x, -z) / 2pi + 0.5, v = -asin(y)/pi + 0.5
    d, _ = _latlong_directions(width, height)
    up = np.clip(d[..., 1:2], 0.0, 1.0)
    zenith, horizon = np.array([0.18, 0.32, 0.85]), np.array([0.75, 0.82, 0.95])
    sky = horizon + (zenith - horizon) * np.sqrt(up)
    ground = np.array([0.22, 0.18, 0.14]) * (1.0 - 0.5 * np.clip(-d[..., 1:2], 0.0, 1.0))
    img = np.where(d[..., 1:2] >= 0.0, sky, ground)
    # in the map's own frame; u_envMatrix's default (x and z negated) puts it at world (0.45, 0.55, 0.70),
    # above and to the right of the default camera
    sun_dir = np.array([-0.45, 0.55, -0.70])
    sun_dir /= np.linalg.norm(sun_dir)
    cos_sun = (d * sun_dir).sum(-1, keepdims=True)
    disc = np.clip((cos_sun - np.cos(np.radians(6.0))) / (1.0 - np.cos(np.radians(6.0))), 0.0, 1.0)
    img = img + 20.0 * disc ** 1.5 * np.array([1.0, 0.93, 0.82])
    return img.astype(np.float32)


def _downsample(img, width, height):
    """One level down: each texel bilinearly sampled at its centre's place in the level above, clamped at the
    edges (what Mesa's mipmap generation does; for even sizes it is the 2x2 box)."""
    src = np.asarray(img, dtype=np.float64)
    h, w = src.shape[:2]
    x = (np.arange(width) + 0.5) * w / width - 0.5
    y = (np.arange(height) + 0.5) * h / height - 0.5
    x0f, y0f = np.floor(x), np.floor(y)
    fx, fy = (x - x0f)[None, :, None], (y - y0f)[:, None, None]
    x0, x1 = np.clip(x0f.astype(int), 0, w - 1), np.clip(x0f.astype(int) + 1, 0, w - 1)
    y0, y1 = np.clip(y0f.astype(int), 0, h - 1), np.clip(y0f.astype(int) + 1, 0, h - 1)
    top = src[y0][:, x0] * (1.0 - fx) + src[y0][:, x1] * fx
    bottom = src[y1][:, x0] * (1.0 - fx) + src[y1][:, x1] * fx
    return (top * (1.0 - fy) + bottom * fy).astype(np.float32)


def mip_chain(img):
    """[level 0, 1, ... 1x1] of an (h, w, c) float image, as OpenGL's glGenerateMipmap sizes them
    (level_sizes)."""
    levels = [np.ascontiguousarray(img, dtype=np.float32)]
    for w, h in level_sizes(img.shape[1], img.shape[0])[1:]:
        levels.append(_downsample(levels[-1], w, h))
    return levels


def _latlong_directions(width, height):
    v = (np.arange(height) + 0.5) / height
    u = (np.arange(width) + 0.5) / width
    uu, vv = np.meshgrid(u, v)
    el, az = (0.5 - vv) * np.pi, (uu - 0.5) * 2.0 * np.pi
    d = np.stack([np.cos(el) * np.sin(az), np.sin(el), -np.cos(el) * np.cos(az)], -1)
    solid_angle = np.cos(el) * (np.pi / height) * (2.0 * np.pi / width)
    return d, solid_angle


def _sh9(d):
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    return np.stack([0.282095 * np.ones_like(x), 0.488603 * y, 0.488603 * z, 0.488603 * x,
                     1.092548 * x * y, 1.092548 * y * z, 0.315392 * (3 * z * z - 1), 1.092548 * x * z,
                     0.546274 * (x * x - y * y)], -1)


SH_BAND_ROWS = 256      # rows of the map projected at a time (float64 copies of at most 256 rows)


def sh9_projection(env):
    """The order-2 spherical-harmonic coefficients (9 x 3, float64) of a lat-long radiance map: the sum over texels
    of radiance x basis x solid angle. The basis is separable on the map: with x = cos(el) sin(az), y = sin(el),
    z = -cos(el) cos(az), every function is a product of one of six azimuthal factors (1, cos, sin, cos^2, sin cos,
    sin^2) and an elevation factor, so each row's radiance is summed against the six (one matrix product per band
    of rows) and the rows then weighted by their elevation factors and solid angles: time and memory grow with
    the map, never as a per-texel table of the basis."""
    h, w = env.shape[:2]
    el = (0.5 - (np.arange(h) + 0.5) / h) * np.pi
    az = ((np.arange(w) + 0.5) / w - 0.5) * 2.0 * np.pi
    ca, sa = np.cos(az), np.sin(az)
    factors = np.stack([np.ones_like(az), ca, sa, ca * ca, sa * ca, sa * sa])         # (6, w)
    ce, se = np.cos(el), np.sin(el)
    weight = ce * (np.pi / h) * (2.0 * np.pi / w)                                      # solid angle of a row's texels
    coeffs = np.zeros((9, 3))
    for r0 in range(0, h, SH_BAND_ROWS):
        r1 = min(h, r0 + SH_BAND_ROWS)
        m = np.matmul(factors, env[r0:r1, :, :3].astype(np.float64)) * weight[r0:r1, None, None]  # (rows, 6, 3)
        one, cos_, sin_, cos2, sincos, sin2 = (m[:, j] for j in range(6))
        c, s = ce[r0:r1, None], se[r0:r1, None]
        coeffs += np.stack([0.282095 * one, 0.488603 * s * one, -0.488603 * c * cos_, 0.488603 * c * sin_,
                            1.092548 * c * s * sin_, -1.092548 * s * c * cos_, 0.315392 * (3 * c * c * cos2 - one),
                            -1.092548 * c * c * sincos, 0.546274 * (c * c * sin2 - s * s * one)], 1).sum(0)
    return coeffs


def irradiance_map(env, width=128, height=64):
    """Irradiance E(n)/pi of a lat-long radiance map, from its order-2 spherical-harmonic projection
    (Ramamoorthi & Hanrahan 2001, "An Efficient Representation for Irradiance Environment Maps")."""
    coeffs = sh9_projection(env)
    band = np.array([np.pi, 2 * np.pi / 3, 2 * np.pi / 3, 2 * np.pi / 3, np.pi / 4, np.pi / 4, np.pi / 4,
                     np.pi / 4, np.pi / 4])
    dn, _ = _latlong_directions(width, height)
    irr = np.einsum("hwk,kc->hwc", _sh9(dn), coeffs * band[:, None]) / np.pi
    return np.clip(irr, 0.0, None).astype(np.float32)


def _rgb(img):
    """An (h, w, c) map as RGB: grey (and grey-and-alpha) as its grey, alpha dropped."""
    if img.shape[2] <= 2:
        return np.repeat(img[..., :1], 3, axis=2)
    return img[..., :3] if img.shape[2] > 3 else img


def load_environment(path, loc=None):
    """A lat-long environment file as float32 RGB (rows top first). Any regular image file within the size caps
    (images.py); one whose decoded floats would pass images.MAX_DECODED_BYTES (a 16384 x 8192 map) is box-filtered
    down by a power of two as it is read. Grey (and grey-and-alpha) maps light as their grey; texels that are
    not finite (NaN, infinite: no radiance) read as 0. Problems: one line at `loc` (default: the file)."""
    from mtlxgen.base.images import read_image
    img = _rgb(read_image(path, loc, "environment file", reduce=True))
    for r0 in range(0, img.shape[0], SH_BAND_ROWS):      # in place, a band of rows at a time
        band = img[r0:r0 + SH_BAND_ROWS]
        band[~np.isfinite(band)] = 0.0
    return img


@dataclass
class Environment:
    """What a host binds for image-based light: arrays to upload and the uniforms' values (prepare())."""
    radiance: list                      # mip chain of the lat-long radiance, level 0 first, (h, w, 3) float32
    irradiance: np.ndarray              # lat-long irradiance / pi, (h, w, 3) float32
    uniforms: dict = field(default_factory=dict)    # application uniform name -> value (matrices column-major)

    @property
    def mips(self):
        return len(self.radiance)


def prepare(source=None, samples=ENV_SAMPLES, intensity=1.0, irradiance_size=IRRADIANCE_SIZE, mips=True):
    """The Environment of a lat-long map: `source` a path (HDR, EXR or any image OpenImageIO reads: load_environment),
    an (h, w, c) array (row 0 on top) or None (render's built-in sky). samples: u_envRadianceSamples (render's 64);
    intensity: u_envLightIntensity. mips=False leaves the chain to the host (radiance holds level 0 alone; the
    uniforms still name the full chain's count, which glGenerateMipmap makes)."""
    if source is None:
        env = builtin_sky()
    elif isinstance(source, (str, bytes)) or hasattr(source, "__fspath__"):
        env = load_environment(source)
    else:
        env = np.asarray(source, dtype=np.float32)
        env = _rgb(env[..., None] if env.ndim == 2 else env)
    env = np.ascontiguousarray(env, dtype=np.float32)
    h, w = env.shape[:2]
    uniforms = {"u_envRadianceMips": mip_count(w, h), "u_envRadianceSamples": int(samples),
                "u_envMatrix": [float(x) for x in np.array(ENV_MATRIX).T.ravel()],
                "u_envLightIntensity": float(intensity)}
    return Environment(mip_chain(env) if mips else [env], irradiance_map(env, *irradiance_size), uniforms)


# ------------------------------------------------------------------ the GGX-prefiltered map (environment "prefiltered")

# (the recipe, PREFILTER_RECIPE, is part of the shaders' application interface: interface.py holds it)

_PREFILTER_VS = """
out vec2 v_uv;
void main()
{
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    v_uv = p;
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
"""

_PREFILTER_MAIN = """
uniform sampler2D u_source;
uniform int u_sourceMips;
uniform int u_level;
uniform int u_samples;
layout(location = 0) out vec4 out_color;
void main()
{
    ivec2 size = max(textureSize(u_source, 0) >> u_level, ivec2(1));
    out_color = vec4(mg_env_prefilter_texel(u_source, u_sourceMips, ivec2(gl_FragCoord.xy), size, u_level,
                                            u_samples), 1.0);
}
"""


def _lib_closure(rel):
    """glsl_lib files `rel` requires, dependencies first, then rel itself: [(rel, text)]."""
    from mtlxgen.emit.emitter import read_lib_file
    order, seen = [], set()

    def visit(r):
        if r in seen:
            return
        seen.add(r)
        for dep in read_lib_file(r)[1]:
            visit(dep)
        order.append((r, read_lib_file(r)[0]))
    visit(rel)
    return order


def prefilter_sources(target="glsl"):
    """(vertex, fragment) GLSL of the prefilter pass: a full-screen triangle (three vertices, no attributes) whose
    fragment writes one texel of one level (uniforms u_source: the box-filtered chain on a unit, u_sourceMips, u_level,
    u_samples). target "glsl" (#version 400) or "essl" (#version 300 es, for WebGL2); the fragment is
    glsl_lib's prefilter code that main() reaches."""
    from mtlxgen.emit import glsldeps
    if target == "essl":
        head = "#version 300 es\nprecision highp float;\nprecision highp int;\nprecision highp sampler2D;\n"
    elif target == "glsl":
        head = "#version 400\n"
    else:
        raise ValueError("target must be glsl or essl, not %r" % (target,))
    code = []
    for rel, text in glsldeps.used_code(_lib_closure(PREFILTER_LIB), [_PREFILTER_MAIN]):
        code.append("// ---- glsl_lib/%s\n%s\n" % (rel, text.rstrip()))
    return head + _PREFILTER_VS, head + "\n".join(code) + _PREFILTER_MAIN


def level_sizes(width, height):
    """(w, h) of each level of a full chain, level 0 first (OpenGL's sizes: halved, rounded down, at least 1)."""
    sizes = [(int(width), int(height))]
    while sizes[-1] != (1, 1):
        w, h = sizes[-1]
        sizes.append((max(1, w // 2), max(1, h // 2)))
    return sizes


def level_alpha(level, width):
    """The GGX alpha level `level` of a prefiltered map holds (glsl_lib mg_env_prefiltered_alpha; 0 for level 0)."""
    return 0.0 if level <= 0 else 2.0 ** level * PREFILTER_TEXELS * 2.0 * np.pi / float(width)


def prefiltered_lod(alpha, width, mips):
    """The level the split-sum lookup reads for roughness alpha (glsl_lib mg_env_prefiltered_lod)."""
    alpha1 = level_alpha(1, width)
    lod = alpha / alpha1 if alpha < alpha1 else 1.0 + np.log2(alpha / alpha1)
    return float(np.clip(lod, 0.0, max(mips - 1, 0)))


class Prefilter:
    """The prefilter pass in a moderngl context (3.3 core or later; float colour targets): run() turns a lat-long
    texture with its box-filtered mip chain into a new float texture whose levels hold the GGX lobes of
    level_alpha(). Each level is drawn into a framebuffer of its size and copied into its level of the result
    through a pixel buffer (GL-side: no round trip through the host). Release when done."""

    def __init__(self, ctx):
        vertex, fragment = prefilter_sources("glsl")
        self.ctx = ctx
        self.prog = ctx.program(vertex_shader=vertex, fragment_shader=fragment)
        self.vao = ctx.vertex_array(self.prog, [])

    def run(self, source, samples=PREFILTER_SAMPLES):
        """The GGX-prefiltered texture (RGBA float32, linear-mipmap-linear, repeat) of `source`, a moderngl
        texture holding the lat-long radiance and its full mip chain."""
        import moderngl
        ctx = self.ctx
        w, h = source.size
        sizes = level_sizes(w, h)
        out = ctx.texture((w, h), 4, dtype="f4")
        out.build_mipmaps(0, len(sizes) - 1)         # allocate every level (overwritten below)
        source.use(0)
        wrap_v, source.repeat_y = source.repeat_y, False      # the poles: reads near one never blend in the other
        self.prog["u_source"].value = 0
        self.prog["u_sourceMips"].value = len(sizes)
        self.prog["u_samples"].value = int(samples)
        pixels = ctx.buffer(reserve=w * h * 16)
        for level, (lw, lh) in enumerate(sizes):
            target = ctx.texture((lw, lh), 4, dtype="f4")
            fbo = ctx.framebuffer(color_attachments=[target])
            try:
                fbo.use()
                fbo.viewport = (0, 0, lw, lh)
                ctx.disable(moderngl.BLEND | moderngl.DEPTH_TEST)
                self.prog["u_level"].value = level
                self.vao.render(moderngl.TRIANGLES, vertices=3)
                fbo.read_into(pixels, components=4, dtype="f4")
                out.write(pixels, viewport=(0, 0, lw, lh), level=level)
            finally:
                fbo.release()
                target.release()
        pixels.release()
        source.repeat_y = wrap_v
        out.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
        out.repeat_y = False            # the poles: a coarse level's top row is not blended with its bottom row
        return out

    def release(self):
        self.vao.release()
        self.prog.release()
