"""pbrlib nodes that compute values, not closures (MaterialX PBR Specification 1.39, "Utility Nodes").

Only the leaf nodedefs are here. glossiness_anisotropy (invert + roughness_anisotropy) and the bxdf
library's value nodes (UsdPrimvarReader_*, UsdTransform2d, UsdUVTexture(_23), gltf_* images,
open_pbr_anisotropy, the *_to_* translation graphs) are nodegraphs in the data libraries and are
expanded. Each GLSL file under glsl_lib/pbrlib/ cites the paper its formula comes from.
"""

_P = "pbrlib/"

_ARTISTIC = "{{reflectivity}}, {{edge_color}}"
_HAIR = "{{longitudinal}}, {{azimuthal}}, "

NODES = {
    "roughness_anisotropy": {"expr": "mg_roughness_anisotropy({{roughness}}, {{anisotropy}})",
                             "files": [_P + "roughness_anisotropy.glsl"]},
    "roughness_dual": {"expr": "mg_roughness_dual({{roughness}})", "files": [_P + "roughness_dual.glsl"]},
    "blackbody": {"expr": "mg_blackbody({{temperature}})", "files": [_P + "blackbody.glsl"]},
    "artistic_ior": {"outputs": {"ior": "mg_artistic_ior_n(" + _ARTISTIC + ")",
                                 "extinction": "mg_artistic_ior_k(" + _ARTISTIC + ")"},
                     "files": [_P + "artistic_ior.glsl"]},
    "deon_hair_absorption_from_melanin": {
        "expr": "mg_deon_hair_absorption_from_melanin({{melanin_concentration}}, {{melanin_redness}}, "
                "{{eumelanin_color}}, {{pheomelanin_color}})",
        "files": [_P + "hair_absorption_from_melanin.glsl"]},
    "chiang_hair_absorption_from_color": {
        "expr": "mg_chiang_hair_absorption_from_color({{color}}, {{azimuthal_roughness}})",
        "files": [_P + "hair_absorption_from_color.glsl"]},
    "chiang_hair_roughness": {"outputs": {"roughness_R": "mg_chiang_hair_roughness(" + _HAIR + "1.0)",
                                          "roughness_TT": "mg_chiang_hair_roughness(" + _HAIR + "{{scale_TT}})",
                                          "roughness_TRT": "mg_chiang_hair_roughness(" + _HAIR + "{{scale_TRT}})"},
                              "files": [_P + "hair_roughness.glsl"]},
}
