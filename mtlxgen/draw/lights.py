"""Light rigs: the lights library's nodes of a document (point_light, directional_light, spot_light) as
the LightData records the renderer binds to u_lightData[] (glsl_lib/lighting/lights.glsl).

A light rig is a .mtlx document of top-level light nodes, like MaterialX's
resources/Lights/san_giuseppe_bridge_split.mtlx. Unset inputs take the nodedef's defaults.
"""
from mtlxgen.base.diagnostics import Loc, MtlxError

# LightData.type: the order of lights_defs.mtlx
LIGHT_TYPES = {"point_light": 1, "directional_light": 2, "spot_light": 3}
_DEFAULTS = {"position": (0.0, 0.0, 0.0), "direction": (0.0, 0.0, -1.0), "color": (1.0, 1.0, 1.0),
             "intensity": 1.0, "decay_rate": 2.0, "inner_angle": 1.0, "outer_angle": 1.0}
_TYPES = {"position": "vector3", "direction": "vector3", "color": "color3"}       # the others: float
from mtlxgen.base.interface import LIGHTS_LIMIT as MAX_LIGHTS     # a rig's lights: at most what a shader takes


def load_light_rig(path):
    """[{type, position, direction, color, intensity, decay_rate, inner_angle, outer_angle}] in document order."""
    from mtlxgen.read.source import load_document
    doc = load_document(path)
    lights = []
    for name in doc.order:
        node = doc.nodes.get(name)
        if node is None or node.category not in LIGHT_TYPES:
            continue
        light = {"type": LIGHT_TYPES[node.category]}
        for member, default in _DEFAULTS.items():
            port = node.inputs.get(member)
            if port is not None and port.connected:
                raise MtlxError((port.loc, "light '%s': input '%s' must be a value in a light rig" % (name, member)))
            if port is not None and port.error:          # a value that does not parse: not the default in silence
                raise MtlxError((port.loc, port.error))
            want = _TYPES.get(member, "float")
            if port is not None and port.type != want:   # no light nodedef takes it: not read as some other type
                raise MtlxError((port.loc, "light '%s': input '%s' is of type %s; a %s's %s is a %s"
                                 % (name, member, port.type, node.category, member, want)))
            value = port.value if port is not None and port.value is not None else default
            light[member] = tuple(float(v) for v in value) if isinstance(default, tuple) else float(value)
        lights.append(light)
    if not lights:
        raise MtlxError((Loc(path, 1), "no point_light, directional_light or spot_light nodes in the light rig"))
    if len(lights) > MAX_LIGHTS:
        raise MtlxError((Loc(path, 1), "%d lights; at most %d are bound" % (len(lights), MAX_LIGHTS)))
    return lights


def bind_lights(prepared, lights):
    """Set u_lightData[i] members and u_numActiveLightSources on a render.Prepared shader (plain uniforms or
    members of its uniform block)."""
    for i, light in enumerate(lights):
        for member, value in light.items():
            prepared.set("u_lightData[%d].%s" % (i, member), value)
    prepared.set("u_numActiveLightSources", len(lights))
