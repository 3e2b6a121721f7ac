"""The lit surface's skeleton, written once for every shading model that lights itself: pbrlib's `surface`
(pbrlib_shading.shade), Stride and Enterprise PBR.

    surfaceshader OUT = surfaceshader(vec3(0.0), vec3(0.0));
    {                                   // lit_surface: the lighting files, the view vectors
        vec3 mg_P = <position_world>;   // the shaded point
        vec3 mg_V = normalize(u_viewPosition - mg_P);   // towards the viewer
        vec3 mg_N = normalize(<normal>);                // where the model shades with one normal
        vec3 mg_L = vec3(0.0);          // towards the light (set by the light loop, or by a model's sampling)
        ... the model's own lines
        for (int mg_i = 0; mg_i < min(u_numActiveLightSources, MG_MAX_LIGHTS); ++mg_i)
        {                               // light_loop, where the shader takes lights (em.max_lights > 0)
            vec3 mg_light;
            mg_sample_light(u_lightData[mg_i], mg_P, mg_L, mg_light);
            ... the model's response to one light
        }
        ... the environment, emission, opacity: the model's
    }
"""
from contextlib import contextmanager

LIGHTING_FILES = ["closures.glsl", "lighting/environment.glsl"]


@contextmanager
def lit_surface(em, stem, files=(), comment=None, normal=None):
    """Writes the surfaceshader variable (named from `stem`, yielded) and opens the lit block: the lighting
    files and `files` required, mg_P, mg_V, mg_N (normalize(`normal`), when given) and mg_L declared. The
    block closes at the end of the `with`."""
    for f in LIGHTING_FILES + list(files):
        em.require(f)
    em.app_uniform("u_viewPosition")
    out = em.fresh(stem + "_out")
    em.line("surfaceshader %s = surfaceshader(vec3(0.0), vec3(0.0));" % out)
    em.open_block(None, comment)
    em.line("vec3 mg_P = %s;" % em.stream("position_world"))
    em.line("vec3 mg_V = normalize(u_viewPosition - mg_P);")
    if normal is not None:
        em.line("vec3 mg_N = normalize(%s);" % normal)
    em.line("vec3 mg_L = vec3(0.0);")
    yield out
    em.close_block()


def takes_lights(em):
    """Whether the shader loops over direct lights: it was asked for (--lights, --max-lights N: em.max_lights).
    Without, a lit surface is lit by the environment alone and declares no light uniforms."""
    return em.max_lights > 0


@contextmanager
def light_loop(em):
    """The loop over the active lights (lighting/lights.glsl), for a shader that takes_lights: inside, mg_L is
    the direction to the light and mg_light the light arriving at mg_P; closures are evaluated in the
    "reflection" context."""
    em.require("lighting/lights.glsl")
    em.line("for (int mg_i = 0; mg_i < min(u_numActiveLightSources, MG_MAX_LIGHTS); ++mg_i)")
    em.open_block("reflection")
    em.line("vec3 mg_light;")
    em.line("mg_sample_light(u_lightData[mg_i], mg_P, mg_L, mg_light);")
    yield
    em.close_block()
