"""Inputs a document names by an older name: one clear line naming the released input instead of a
generic "no nodedef takes inputs" (graph/build.py asks here when a node's input matches no nodedef).

OpenPBR Surface: the 2023 draft (OpenPBR Surface draft specification v0.0, 2023-04-06) against the
released ND_open_pbr_surface_surfaceshader (1.1). Entries whose value is None have no released
counterpart; the message then says what replaces them, where anything does.
"""

OPEN_PBR_DRAFT = {
    # base
    "base": "base_weight",
    "base_roughness": "base_diffuse_roughness",
    "metal": "base_metalness",
    "metalness": "base_metalness",
    "base_metalness_weight": "base_metalness",
    # specular
    "specular": "specular_weight",
    "specular_IOR": "specular_ior",
    "specular_anisotropy": "specular_roughness_anisotropy",
    "specular_rotation": None,
    "specular_scale": None,
    "metal_edge_tint": "specular_color",
    # transmission
    "transmission": "transmission_weight",
    "transmission_abbe_number": "transmission_dispersion_abbe_number",
    "transmission_extra_roughness": None,
    # subsurface
    "subsurface": "subsurface_weight",
    "subsurface_scale": "subsurface_radius_scale",
    "subsurface_anisotropy": "subsurface_scatter_anisotropy",
    # coat
    "coat": "coat_weight",
    "coat_IOR": "coat_ior",
    "coat_anisotropy": "coat_roughness_anisotropy",
    "coat_rotation": None,
    "coat_normal": "geometry_coat_normal",
    "coat_ignore_color": None,
    "coat_ignore_roughness": None,
    "coat_ignore_ior": None,
    # fuzz (the draft's sheen-like layer)
    "fuzz": "fuzz_weight",
    "sheen": "fuzz_weight",
    "sheen_color": "fuzz_color",
    "sheen_roughness": "fuzz_roughness",
    # emission
    "emission": "emission_luminance",
    "emission_weight": "emission_luminance",
    # thin film
    "thin_film_IOR": "thin_film_ior",
    # geometry
    "opacity": "geometry_opacity",
    "thin_walled": "geometry_thin_walled",
    "normal": "geometry_normal",
    "tangent": "geometry_tangent",
    "coat_tangent": "geometry_coat_tangent",
}

_REPLACED_BY = {
    "specular_rotation": "orient the anisotropy with geometry_tangent",
    "coat_rotation": "orient the coat's anisotropy with geometry_coat_tangent",
    "specular_scale": "set specular_ior (or specular_weight) instead",
    "coat_ignore_color": "coat_darkening controls the coat's darkening",
}

RENAMED = {"open_pbr_surface": (OPEN_PBR_DRAFT, "the 2023 draft name")}


def renamed_input_message(category, name):
    """The one-line problem for an input named by an older name, or None where it is not one."""
    table = RENAMED.get(category)
    if table is None or name not in table[0]:
        return None
    released = table[0][name]
    if released is not None:
        return "%s input '%s' is %s; the released input is '%s'" % (category, name, table[1], released)
    hint = _REPLACED_BY.get(name)
    return "%s input '%s' is %s; the released node has no such input%s" % (
        category, name, table[1], "; " + hint if hint else "")
