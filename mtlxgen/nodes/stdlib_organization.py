"""stdlib organisation, constants, materials and application nodes."""

NODES = {
    "dot": {"expr": "{{in}}", "evaluate": lambda i, t, o: i["in"]},
    "constant": {"expr": "{{value}}", "evaluate": lambda i, t, o: i["value"]},
    "surfacematerial": "{{surfaceshader}}",
    "volumematerial": "surfaceshader({{volumeshader}}.color, {{volumeshader}}.transparency)",
    "time": {"expr": "mg_time({{fps}})", "files": ["stdlib/application/time.glsl"]},
    "frame": {"expr": "mg_frame()", "files": ["stdlib/application/time.glsl"]},
}
