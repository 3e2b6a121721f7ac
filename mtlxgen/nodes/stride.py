"""The Stride material (glsl_lib/stride/stride_defs.mtlx: ND_stride_material_surfaceshader).

Stride's material attributes (Stride manual, "Shading attributes"; formulas in
docs/material-models.md sec. 5) choose one model per slot with uniform string inputs: the diffuse
model (Lambert, cel shading with a default / black-and-white / texture ramp), the specular workflow
(metalness, or a specular map with optional energy conservation), and the microfacet specular's
Fresnel, visibility and normal distribution. The handler reads those choices at generation time and
emits calls to the chosen functions of glsl_lib/stride/ only, in the lit-surface skeleton
every lit shading model shares (lit_surface.py):

- direct lights (u_lightData, mg_sample_light): diffuse/pi * light * NL (or the cel ramp of NL)
  + F V D / 4 * light * NL;
- environment: the diffuse colour times the irradiance map (Lambert, for cel shading too), plus the
  specular lobe integrated by importance sampling the selected NDF (u_envRadianceSamples Hammersley
  points, filtered mip lookups), each sample weighted by the selected Fresnel and visibility, so the
  environment shows the same model as the lights;
- emissive rgb * intensity added; use_alpha makes emissive.a the surface's opacity (the colour is
  scaled by it and the transparency blended to 1, as `surface` does with opacity). Thin glass also
  lets its view-based transmittance through as transparency.
"""
from mtlxgen.base.diagnostics import MtlxError
from mtlxgen.nodes.lit_surface import light_loop, lit_surface, takes_lights

FILES = ["stride/fresnel.glsl", "stride/visibility.glsl", "stride/ndf.glsl", "stride/diffuse.glsl",
         "stride/environment.glsl"]

# Fresnel of the half-vector cosine {LH}; thin glass is view based and computed once (mg_glass)
FRESNEL = {
    "schlick": "mg_stride_fresnel_schlick(mg_f0, {LH})",
    "thin_glass": "mg_glass",
    "none": "mg_stride_fresnel_none(mg_f0)",
}
CEL_RAMP = {"default": "mg_stride_cel_default({x})", "black_white": "mg_stride_cel_black_white({x})",
            "texture": "mg_stride_cel_texture({sampler}, {x})"}


def choice(node, em, name):
    """The value of a uniform string enum input, checked against the nodedef's enum list."""
    src = node.inputs[name]
    if src.linked:
        em.fail(node, "input '%s' must be a constant, it is connected" % name)
    decl = node.nodedef.inputs[name]
    allowed = [v.strip() for v in (decl.enumvalues or decl.enum or "").split(",") if v.strip()]
    value = node.static.get(name) or decl.value
    if value not in allowed:
        raise MtlxError((src.loc or node.loc, "node '%s' (%s): %s '%s' is not one of %s"
                         % (node.id, node.nodedef.name, name, value, ", ".join(allowed))))
    return value


def _specular_terms(em, fresnel, vis, ndf):
    """Lines giving mg_NL, mg_NH, mg_LH, mg_F, mg_Vis, mg_D for the direction mg_L and half vector mg_H."""
    em.line("float mg_NL = max(dot(mg_N, mg_L), 1.0e-4);")
    em.line("float mg_NH = clamp(dot(mg_N, mg_H), 0.0, 1.0);")
    em.line("float mg_LH = clamp(dot(mg_L, mg_H), 0.0, 1.0);")
    em.line("vec3 mg_F = %s;" % FRESNEL[fresnel].format(LH="mg_LH"))
    em.line("float mg_Vis = mg_stride_vis_%s(mg_alpha, mg_NL, mg_NV, mg_NH, mg_LH);" % vis)
    em.line("float mg_D = mg_stride_ndf_%s(mg_alpha, mg_NH);" % ndf)


def stride_material(node, em):
    diffuse_model = choice(node, em, "diffuse_model")
    cel_ramp = choice(node, em, "cel_ramp") if diffuse_model == "cel_shading" else None
    workflow = choice(node, em, "workflow")
    fresnel, vis, ndf = (choice(node, em, n) for n in ("fresnel", "visibility", "ndf"))
    i = lambda name: em.input_expr(node, name)

    ramp_src = node.inputs["cel_ramp_texture"]
    sampler = ramp_src.uniform
    if cel_ramp == "texture":
        if sampler is None or not str(em.uniform(sampler).value or ""):
            raise MtlxError((ramp_src.loc or node.loc, "node '%s' (%s): cel_ramp 'texture' needs a cel_ramp_texture file"
                             % (node.id, node.nodedef.name)))
        em.textures[sampler] = {"uaddressmode": "clamp", "vaddressmode": "clamp", "filtertype": "linear",
                                "default": None}
    elif sampler:
        em.drop_unread_uniform(sampler, node)      # no ramp texture read: no sampler to bind

    comment = "Stride material: %s diffuse, %s workflow, %s Fresnel, %s visibility, %s NDF" % (
        diffuse_model if cel_ramp is None else "cel_shading/" + cel_ramp, workflow, fresnel, vis, ndf)
    with lit_surface(em, node.id, FILES, comment, normal=i("normal")) as out:
        _stride_body(node, em, out, i, diffuse_model, cel_ramp, workflow, fresnel, vis, ndf, sampler)
    return {"out": out}


def _stride_body(node, em, out, i, diffuse_model, cel_ramp, workflow, fresnel, vis, ndf, sampler):
    """The model's lines inside the lit-surface skeleton (lit_surface.py)."""
    em.line("float mg_NV = max(dot(mg_N, mg_V), 1.0e-4);")
    em.line("float mg_gloss = clamp(%s, 0.0, 1.0);" % i("glossiness"))
    em.line("float mg_alpha = max((1.0 - mg_gloss) * (1.0 - mg_gloss), 0.001);")
    # specular colour and the diffuse colour left beside it (Stride docs, "Metalness map" / "Specular map")
    if workflow == "metalness":
        em.line("float mg_metal = clamp(%s, 0.0, 1.0);" % i("metalness"))
        em.line("vec3 mg_f0 = mix(vec3(0.02), %s, mg_metal);" % i("diffuse"))
        em.line("vec3 mg_diffuse = mix(%s, vec3(0.0), mg_metal);" % i("diffuse"))
    else:
        em.line("vec3 mg_f0 = %s * %s;" % (i("specular"), i("specular_intensity")))
        if em.static(node, "energy_conservation"):
            em.line("vec3 mg_diffuse = %s * max(vec3(1.0) - mg_f0, vec3(0.0));" % i("diffuse"))
        else:
            em.line("vec3 mg_diffuse = %s;" % i("diffuse"))
    if fresnel == "thin_glass":
        em.line("vec3 mg_transmittance;")
        em.line("vec3 mg_glass = mg_stride_thin_glass(mg_f0, mg_NV, %s, mg_transmittance);" % i("ior"))

    if takes_lights(em):
        with light_loop(em):
            em.line("vec3 mg_H = mg_L + mg_V;")
            em.line("mg_H /= max(length(mg_H), 1.0e-6);")
            _specular_terms(em, fresnel, vis, ndf)
            if diffuse_model == "lambert":
                em.line("%s.color += mg_diffuse / MG_PI * mg_light * mg_NL;" % out)
            elif diffuse_model == "cel_shading":
                ramp = CEL_RAMP[cel_ramp].format(x="mg_NL", sampler=sampler)
                em.line("%s.color += mg_diffuse / MG_PI * mg_light * %s;" % (out, ramp))
            em.line("%s.color += mg_F * (mg_Vis * mg_D / 4.0) * mg_light * mg_NL;" % out)

    # environment
    em.open_block("indirect", "environment: Lambert irradiance and the specular lobe, importance-sampled")
    if diffuse_model != "none":
        em.line("%s.color += mg_diffuse * mg_env_irradiance(mg_N);" % out)
    em.line("int mg_n = max(u_envRadianceSamples, 1);")
    em.line("vec3 mg_specular = vec3(0.0);")
    em.line("int mg_texels = mg_env_texels();")
    em.line("for (int mg_s = 0; mg_s < mg_n; ++mg_s)")
    em.open_block("indirect")
    em.line("vec2 mg_xi = mg_env_sample_point(mg_s, mg_n);")
    em.line("vec3 mg_H = mg_stride_half_vector(mg_N, mg_stride_sample_%s(mg_alpha, mg_xi.x), MG_TWO_PI * mg_xi.y);"
            % ndf)
    em.line("mg_L = reflect(-mg_V, mg_H);")
    em.line("if (dot(mg_N, mg_L) <= 0.0)")
    with em.indented():
        em.line("continue;")
    _specular_terms(em, fresnel, vis, ndf)
    em.line("// density of mg_L: D NH / (4 LH); the estimate F V D/4 NL / pdf = F V NL LH / NH")
    em.line("float mg_pdf = mg_D * mg_NH / (4.0 * max(mg_LH, 1.0e-4));")
    em.line("mg_specular += mg_env_radiance(mg_L, mg_env_lod(mg_L, mg_pdf, mg_texels, mg_env_sample_total(mg_n))) * mg_F"
            " * (mg_Vis * mg_NL * mg_LH / max(mg_NH, 1.0e-4));")
    em.close_block()
    em.line("%s.color += mg_specular / float(mg_n);" % out)
    em.close_block()

    # emissive (Stride docs, "Emissive"): colour += rgb * intensity; use alpha: alpha = emissive.a
    em.line("vec4 mg_emissive = %s;" % i("emissive"))
    em.line("%s.color += mg_emissive.rgb * max(%s, 0.0);" % (out, i("emissive_intensity")))
    if fresnel == "thin_glass":
        em.line("%s.transparency = mg_transmittance;" % out)
    if em.static(node, "use_alpha"):
        em.line("float mg_opacity = clamp(mg_emissive.a, 0.0, 1.0);")
        em.line("%s.color *= mg_opacity;" % out)
        em.line("%s.transparency = mix(vec3(1.0), %s.transparency, mg_opacity);" % (out, out))


NODES = {"stride_material": {"handler": stride_material}}
