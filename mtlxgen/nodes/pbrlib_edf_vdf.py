"""EDFs and VDFs of pbrlib that MaterialX's own GLSL does not generate (MaterialX Specification 1.39):
conical_edf, measured_edf (IES LM-63 profiles, mtlxgen/draw/ies.py), absorption_vdf, anisotropic_vdf, the
`volume` shader constructor, and the layer of a BSDF over a VDF. (mix / add / multiply of VDFs are the
closure combinators of stdlib_compositing and pbrlib_shading; mix_volumeshader and
mix_displacementshader are stdlib_compositing's.)

An EDF is evaluated in the "emission" context, where mg_V points from the surface to the viewer.
A VDF matters only in the "transmission" context (what is seen through a surface): there it is the
Beer–Lambert transmittance over a fixed path length (glsl_lib/pbrlib/vdf/absorption.glsl) and
what the medium scatters towards the eye; in every other context it is the empty VDF, so layering a
BSDF over it changes only transmission.
measured_edf's `file` is a texture like an image's: the manifest's texture entry names the .ies file
(an application turns it into the 2-D texture with mtlxgen.draw.ies.load_texture, as draw/renderer.py does).
"""

_EDF = "pbrlib/edf/"
_VDF = "pbrlib/vdf/"


def volume(node, em):
    """volumeshader from a VDF and an EDF: colour = what the medium scatters + what it emits,
    transparency = its transmittance along the view (both evaluated at the shaded point)."""
    out = em.fresh(node.id + "_out")
    em.line("volumeshader %s = volumeshader(vec3(0.0), vec3(1.0));" % out)
    vdf, edf = node.inputs["vdf"], node.inputs["edf"]
    if vdf.linked or edf.linked:
        em.require("closures.glsl")
        em.app_uniform("u_viewPosition")
        em.open_block(None, "volume")
        em.line("vec3 mg_P = %s;" % em.stream("position_world"))
        em.line("vec3 mg_V = normalize(u_viewPosition - mg_P);")
        em.line("vec3 mg_L = vec3(0.0);")
        em.line("float mg_occlusion = 1.0;")
        if vdf.linked:
            v = em.closure(vdf, "transmission")
            em.line("%s.color += %s.response;" % (out, v))
            em.line("%s.transparency = %s.throughput;" % (out, v))
        if edf.linked:
            em.line("%s.color += %s;" % (out, em.closure(edf, "emission")))
        em.close_block()
    return {"out": out}


NODES = {
    "conical_edf": {
        "closure": {"emission": "mg_conical_edf(mg_V, {{color}}, {{normal}}, {{inner_angle}}, {{outer_angle}})"},
        "files": [_EDF + "conical.glsl"]},
    "measured_edf": {
        "closure": {"emission": "mg_measured_edf({{file}}, mg_V, {{color}}, {{normal}})"},
        "files": [_EDF + "measured.glsl"]},
    "absorption_vdf": {
        "closure": {"transmission": "mg_absorption_vdf({{absorption}})"},
        "files": [_VDF + "absorption.glsl"]},
    "anisotropic_vdf": {
        "closure": {"transmission": "mg_anisotropic_vdf({{absorption}}, {{scattering}}, {{anisotropy}}, "
                                    "{{@normal_world}}, mg_V)"},
        "files": [_VDF + "anisotropic.glsl"]},
    "volume": {"handler": volume},
}

NODEDEFS = {
    "ND_layer_vdf": {"expr": "mg_layer({{top}}, {{base}})", "files": [_VDF + "layer_vdf.glsl"]},
}
