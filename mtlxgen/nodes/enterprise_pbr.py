"""The Enterprise PBR material (glsl_lib/enterprise/enterprise_pbr_defs.mtlx: ND_enterprise_pbr_surfaceshader).

Dassault Systemes' DSPBR 2025x (docs/material-models.md sec. 3): the handler fills the GLSL struct
MgEpbr from the node's inputs and lights it in the lit-surface skeleton (lit_surface.py); the physics is
in glsl_lib/enterprise/ (one concern a file, see enterprise_pbr.glsl for the layering):

- direct lights (u_lightData, mg_sample_light): light * f(l, v) * |n.l|, f = mg_epbr_bsdf (reciprocal;
  light from behind reaches only the translucent diffuse);
- environment: mg_epbr_environment, every lobe's normalised importance-sampled radiance times its
  tabulated albedo, the diffuse complement times the irradiance, what a transparent surface lets through
  (thin-walled straight through, else refracted through a solid sphere with Beer-Lambert attenuation);
- emission under the coat; cutoutOpacity scales the colour and makes the rest transparent.

Layers whose weight is an unconnected zero in the document (clearcoat, sheenColor, flakeCoverage,
thinFilm) are compiled out: the struct gets the literal 0 instead of the public uniform, so the GLSL
compiler folds their branches away (the uniform stays declared, unused). Connect the input, or give
it a non-zero value, to keep the layer adjustable at run time.

The energy tables are glsl_lib/enterprise/tables.glsl, written by tools/enterprise_tables.py.
"""
from mtlxgen.nodes.lit_surface import light_loop, lit_surface, takes_lights

FILES = ["enterprise/enterprise_pbr.glsl"]

# struct member <- input, in the order of MgEpbr
MEMBERS = ["albedo", "metallic", "roughness", "anisotropy", "anisotropyRotation", "translucency", "translucencyColor",
           "transparency", "specular", "specularTint", "thinFilm", "thinFilmThickness", "thinFilmIor", "sheenColor",
           "sheenRoughness", "flakeCoverage", "flakeColor", "flakeSize", "flakeRoughness", "flipFlop", "flipFlopColor",
           "clearcoat", "clearcoatRoughness", "emissionColor", "emissionValue", "thinWalled", "ior", "attenuationColor",
           "attenuationDistance", "subsurfaceColor", "subsurfaceAnisotropy"]


# layer weights that, as an unconnected zero, compile their layer out
OPTIONAL_LAYERS = {"clearcoat": "0.0", "sheenColor": "vec3(0.0)", "flakeCoverage": "0.0", "thinFilm": "0.0"}


def _layer_off(node, name):
    src = node.inputs[name]
    value = src.value if src.value is not None else node.nodedef.inputs[name].value
    if src.linked or value is None:
        return False
    return all(float(v) == 0.0 for v in (value if isinstance(value, (tuple, list)) else (value,)))


def enterprise_pbr(node, em):
    def i(name):
        if name in OPTIONAL_LAYERS and _layer_off(node, name):
            return OPTIONAL_LAYERS[name]
        return em.input_expr(node, name)
    with lit_surface(em, node.id, FILES, "Enterprise PBR (DSPBR 2025x)") as out:
        em.line("MgEpbr mg_m;")
        for name in MEMBERS:
            em.line("mg_m.%s = %s;" % (name, i(name)))
        em.line("mg_m.N = normalize(%s);" % i("normal"))
        em.line("mg_m.T = %s;" % i("tangent"))
        em.line("mg_m.Nc = normalize(%s);" % i("clearcoatNormal"))
        em.line("mg_m.P = mg_P;")
        em.line("mg_m.footprint = length(fwidth(mg_P));")
        em.line("MgEpbrLobes mg_k = mg_epbr_lobes(mg_m);")
        if takes_lights(em):
            with light_loop(em):
                em.line("%s.color += mg_light * mg_epbr_bsdf(mg_m, mg_k, mg_L, mg_V) * abs(dot(mg_k.frame[2], "
                        "mg_L));" % out)
        em.line("%s.color += mg_epbr_environment(mg_m, mg_k, mg_V);" % out)
        em.line("%s.color += mg_epbr_emission(mg_m, mg_k, mg_V);" % out)
        em.line("float mg_opacity = clamp(%s, 0.0, 1.0);" % i("cutoutOpacity"))
        em.line("%s.color *= mg_opacity;" % out)
        em.line("%s.transparency = vec3(1.0 - mg_opacity);" % out)
    return {"out": out}


NODES = {"enterprise_pbr": {"handler": enterprise_pbr}}
