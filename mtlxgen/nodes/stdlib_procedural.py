"""stdlib procedural nodes (MaterialX Specification 1.39, "Procedural Nodes").

Only the leaf nodedefs are here; ramp, ramp4, ramp_gradient, the shapes (line, circle, hexagon,
checkerboard, tiled*), unifiednoise, randomfloat/randomcolor and the color/FA noise variants are
nodegraphs in the data libraries and are expanded. The GLSL functions are overloaded on the
argument types, so one template serves every output type of a category.
"""

_P = "stdlib/procedural/"

NODES = {
    "noise2d": {"expr": "mg_noise2d({{amplitude}}, {{pivot}}, {{texcoord}})", "files": [_P + "noise.glsl"]},
    "noise3d": {"expr": "mg_noise3d({{amplitude}}, {{pivot}}, {{position}})", "files": [_P + "noise.glsl"]},
    "fractal2d": {"expr": "mg_fractal2d({{amplitude}}, {{octaves}}, {{lacunarity}}, {{diminish}}, {{texcoord}})",
                  "files": [_P + "fractal.glsl"]},
    "fractal3d": {"expr": "mg_fractal3d({{amplitude}}, {{octaves}}, {{lacunarity}}, {{diminish}}, {{position}})",
                  "files": [_P + "fractal.glsl"]},
    "cellnoise2d": {"expr": "mg_cellnoise({{texcoord}})", "files": [_P + "cellnoise.glsl"]},
    "cellnoise3d": {"expr": "mg_cellnoise({{position}})", "files": [_P + "cellnoise.glsl"]},
    "worleynoise2d": {"expr": "mg_worley_{{$type}}({{texcoord}}, {{jitter}}, {{style}})",
                      "files": [_P + "worley.glsl"]},
    "worleynoise3d": {"expr": "mg_worley_{{$type}}({{position}}, {{jitter}}, {{style}})",
                      "files": [_P + "worley.glsl"]},
    "ramplr": "mix({{valuel}}, {{valuer}}, clamp(({{texcoord}}).x, 0.0, 1.0))",
    "ramptb": "mix({{valueb}}, {{valuet}}, clamp(({{texcoord}}).y, 0.0, 1.0))",
    "splitlr": {"expr": "mix({{valuel}}, {{valuer}}, mg_aastep({{center}}, ({{texcoord}}).x))",
                "files": [_P + "split.glsl"]},
    "splittb": {"expr": "mix({{valueb}}, {{valuet}}, mg_aastep({{center}}, ({{texcoord}}).y))",
                "files": [_P + "split.glsl"]},
}

# flake2d / flake3d: every output reads the one flake lookup (an MgFlake struct). The pattern is our own
# construction (MaterialX publishes no algorithm for it): it does not reproduce MaterialX's render.
_FLAKE_ARGS = "{{size}}, {{roughness}}, {{coverage}}, %s, {{normal}}, {{tangent}}, {{bitangent}}"
_FLAKE2D = "mg_flake2d(" + _FLAKE_ARGS % "{{texcoord}}" + ")"
_FLAKE3D = "mg_flake3d(" + _FLAKE_ARGS % "{{position}}" + ")"
NODES["flake2d"] = {"outputs": {"id": _FLAKE2D + ".id", "rand": _FLAKE2D + ".rand", "presence": _FLAKE2D + ".presence",
                                "flakenormal": _FLAKE2D + ".normal"}, "files": [_P + "flake.glsl"]}
NODES["flake3d"] = {"outputs": {"id": _FLAKE3D + ".id", "rand": _FLAKE3D + ".rand", "presence": _FLAKE3D + ".presence",
                                "flakenormal": _FLAKE3D + ".normal"}, "files": [_P + "flake.glsl"]}
