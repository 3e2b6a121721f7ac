"""stdlib shader nodes: surface_unlit (MaterialX Specification 1.39, "Shader Nodes")."""

NODES = {
    "surface_unlit": {"expr": "mg_surface_unlit({{emission}}, {{emission_color}}, {{transmission}}, "
                              "{{transmission_color}}, {{opacity}})",
                      "files": ["stdlib/shader/surface_unlit.glsl"]},
}
