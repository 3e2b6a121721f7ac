"""The application interface: the uniforms a renderer binds besides the material's own inputs.

One table, read by the emitter (which declares the ones a shader reads, per target), the manifest (which
lists them with their defaults for targets without initializers) and draw/renderer.py (which binds them). The
names and meanings are MaterialX GenGlsl's (../shared/docs/interface.md), so a viewer that binds MaterialX's
programs binds ours; the defaults are what a shader draws with when the application sets nothing.

A glsl_lib file that reads one names it in a `// uniforms: NAME ...` header line (emit.read_lib_file); a
handler asks for one with Emitter.app_uniform; a stream's vertex expression lists the ones it needs.
"""
import os
from mtlxgen.base.records import dataclass

MAX_LIGHTS = 8          # u_lightData's length (MG_MAX_LIGHTS in the GLSL) where a shader is asked for lights
                        # without a number (the viewer's rig); a shader takes as many as --max-lights says
LIGHTS_LIMIT = 16       # the most a shader takes: 16 records are 80 vec4 uniforms, within GL 4's fragment limit

ENV_MATRIX = (-1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 1.0)
IDENTITY = (1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0)

# The light record u_lightData[] holds (lights.py fills it; glsl_lib/lighting/lights.glsl reads it): type 1 point,
# 2 directional, 3 spot (the order of lights_defs.mtlx), 0 unused; spot angles are cosines.
LIGHT_STRUCT_NAMES = frozenset(("LightData", "MG_MAX_LIGHTS"))     # names the declarations below take
LIGHT_DATA = (("type", "int"), ("position", "vec3"), ("direction", "vec3"), ("color", "vec3"),
              ("intensity", "float"), ("decay_rate", "float"), ("inner_angle", "float"), ("outer_angle", "float"))


@dataclass(frozen=True)
class AppUniform:
    name: str
    type: str              # GLSL type (of one element, for arrays)
    default: object        # a number, a tuple (vectors; matrices column-major), None: no value (samplers, structs)
    meaning: str
    length: int = 0        # array length; 0: not an array

    @property
    def array_suffix(self):
        return "[MG_MAX_LIGHTS]" if self.name == "u_lightData" else ("[%d]" % self.length if self.length else "")


TABLE = {u.name: u for u in [
    AppUniform("u_worldMatrix", "mat4", IDENTITY, "object to world"),
    AppUniform("u_viewProjectionMatrix", "mat4", IDENTITY,
               "world to clip: gl_Position = u_viewProjectionMatrix * u_worldMatrix * p"),
    AppUniform("u_worldInverseTransposeMatrix", "mat4", IDENTITY, "normals, object to world"),
    AppUniform("u_worldInverseMatrix", "mat4", IDENTITY, "world to object"),
    AppUniform("u_viewPosition", "vec3", (0.0, 0.0, 0.0), "camera position, world space"),
    AppUniform("u_envMatrix", "mat4", ENV_MATRIX, "environment rotation (world direction to lat-long frame)"),
    AppUniform("u_envRadiance", "sampler2D", None, "lat-long HDR radiance with a full mip chain"),
    AppUniform("u_envIrradiance", "sampler2D", None, "lat-long irradiance"),
    AppUniform("u_envLightIntensity", "float", 1.0, "environment multiplier"),
    AppUniform("u_envRadianceMips", "int", 1, "u_envRadiance's mip count, floor(log2(max(w, h))) + 1"),
    AppUniform("u_envRadianceSamples", "int", 16, "samples per lobe for filtered importance sampling"),
    AppUniform("u_envSampleFrame", "int", 0, "progressive refinement: this frame's index"),
    AppUniform("u_envSampleFrames", "int", 1, "progressive refinement: frames accumulated (1: none)"),
    AppUniform("u_numActiveLightSources", "int", 0, "direct lights in u_lightData"),
    AppUniform("u_lightData", "LightData", None, "direct lights (struct LightData)", MAX_LIGHTS),
    AppUniform("u_frame", "float", 0.0, "frame number (the time and frame nodes)"),
    AppUniform("u_vdfThickness", "float", 1.0, "path length through a volume (scene units)"),
]}

SAMPLER_TYPES = ("sampler2D",)

# Progressive refinement's pair: a reduced shader, made for one use, reads them as constants at their defaults (one
# frame's estimate: the progressive sample points' code folds away) unless `--keep` names either (passes/reduce.py:
# both are then kept). The complete interface always has them.
PROGRESSIVE = ("u_envSampleFrame", "u_envSampleFrames")


def types_needed(names, max_lights=MAX_LIGHTS):
    """GLSL declarations the named uniforms' types need before them (the light record and its length)."""
    if "u_lightData" not in names:
        return []
    return ["#define MG_MAX_LIGHTS %d" % max_lights,
            "struct LightData { %s };" % " ".join("%s %s;" % (t, n) for n, t in LIGHT_DATA)]


def glsl_value(u):
    """The GLSL initializer of a uniform's default (None for those without one)."""
    d = u.default
    if d is None:
        return None
    if u.type == "int":
        return str(int(d))
    if u.type == "float":
        return _float(d)
    if u.type == "mat4" and d == IDENTITY:
        return "mat4(1.0)"
    return "%s(%s)" % (u.type, ", ".join(_float(x) for x in d))


def _float(x):
    r = repr(float(x))
    return r if ("." in r or "e" in r) else r + ".0"


def manifest_entry(u, max_lights=MAX_LIGHTS, environment=None):
    """The manifest's record of an application uniform: name, GLSL type, default, meaning. environment "prefiltered":
    u_envRadiance's record says what to bind instead of the box-filtered chain, and `prefilter` holds the recipe
    (PREFILTER_RECIPE below, docs/interface.md "The prefiltered environment")."""
    entry = {"name": u.name, "type": u.type + u.array_suffix.replace("MG_MAX_LIGHTS", str(max_lights)),
             "default": list(u.default) if isinstance(u.default, tuple) else u.default, "meaning": u.meaning}
    if u.name == "u_envRadiance" and environment == "prefiltered":
        entry["meaning"] = "lat-long HDR radiance, GGX-prefiltered per mip level (prefilter: the recipe)"
        entry["prefilter"] = dict(PREFILTER_RECIPE)
    if u.name == "u_lightData":
        entry["members"] = [{"name": n, "type": t} for n, t in LIGHT_DATA]
    return entry


def relative_textures(manifest, folder):
    """`manifest` with each texture file that is an absolute path made relative to `folder` (where the manifest is
    written: a consumer joins the manifest's folder and the name). A file on another drive (Windows) stays absolute;
    a name that resolved to no file stays as the document wrote it."""
    textures = manifest.get("textures")
    if not textures:
        return manifest
    base = os.path.abspath(folder)
    out = []
    for t in textures:
        f = t.get("file")
        if f and os.path.isabs(f):
            try:
                t = dict(t, file=os.path.relpath(f, base).replace(os.sep, "/"))
            except ValueError:          # another drive
                pass
        out.append(t)
    return dict(manifest, textures=out)


def absolute_textures(manifest, folder):
    """The inverse of relative_textures for a manifest read from `folder`: each relative texture file joined to it
    (what a host reading NAME.json does before opening the files)."""
    textures = manifest.get("textures")
    if not textures:
        return manifest
    base = os.path.abspath(folder)
    return dict(manifest, textures=[dict(t, file=os.path.normpath(os.path.join(base, t["file"])))
                                    if t.get("file") and not os.path.isabs(t["file"]) else t for t in textures])


# ---------------------------------------------------------------- the prefiltered environment's recipe
# (environment.Prefilter carries it out; docs/interface.md "The prefiltered environment")

PREFILTER_SAMPLES = 256     # GGX samples per texel of a prefiltered level (each a filtered lookup of the box chain)
PREFILTER_TEXELS = 2.0      # glsl_lib MG_ENV_PREFILTER_TEXELS: level l holds alpha_l = 2^l K 2 pi / w
PREFILTER_LIB = "lighting/environment_prefilter.glsl"

# The recipe a host follows for shaders whose manifest says "environment": "prefiltered" (written into the manifest's
# application entry of u_envRadiance, docs/interface.md "The prefiltered environment"): what prefilter() does here
# and the web pages' script does in WebGL2.
PREFILTER_RECIPE = {
    "method": "ggx",
    "source": "the lat-long radiance with its box-filtered mip chain (as for fis), linear-mipmap-linear, repeat",
    "levels": "as many as the source's; level l is floor(w / 2^l) x floor(h / 2^l), each at least 1",
    "level_alpha": "level 0: the map itself; level l >= 1: alpha_l = 2^l * 2 * 2 pi / w (w: level 0's width)",
    "texel": "direction of uv = (texel + 0.5) / level size: elevation (0.5 - v) pi, azimuth (u - 0.5) 2 pi, "
             "d = (cos e sin a, sin e, -cos e cos a), in the map's frame (no u_envMatrix)",
    "integral": "sum over samples of L(l) G1(l) / sum of G1(l) (Smith masking), n = v = d, halfway vectors drawn from GGX D(h)(n.h) "
                "at Hammersley points; each read at the source level 0.5 log2(1 / (samples pdf texel solid "
                "angle)) + 1, pdf = D(h) / 4, texel solid angle 2 pi^2 cos(e) / (w h)",
    "samples": PREFILTER_SAMPLES,
    "glsl": "glsl_lib/" + PREFILTER_LIB + " (mg_env_prefilter_texel); mtlxgen.draw.environment.prefilter_sources()",
    "lookup": "mg_env_prefiltered_lobe: an isotropic lobe is one read at level mg_env_prefiltered_lod(alpha) - 0.3 "
              "(at least 0; the lod: alpha / alpha_1 below alpha_1, else 1 + log2(alpha / alpha_1), clamped to the "
              "chain), along the mirror direction pulled to the normal with roughness; an anisotropic lobe (a, b), "
              "a > b, is 12 such reads "
              "of roughness b about normals spread along its major axis (slopes at the quantiles of GGX's marginal "
              "slope, scaled by sqrt(a^2 - b^2)), weighted by v.h / n.h; times the split-sum albedo of "
              "glsl_lib/pbrlib/microfacet/albedo.glsl",
    "sampler": "linear-mipmap-linear, repeat in u, clamp to edge in v",
}
