"""stdlib adjustment nodes (MaterialX Specification 1.39, "Adjustment Nodes").

contrast, range, hsvadjust, saturate, colorcorrect and most smoothstep types are nodegraphs in the
data library.
"""

NODES = {
    # linear map of [inlow, inhigh] onto [outlow, outhigh], unclamped
    "remap": "{{outlow}} + ({{in}} - {{inlow}}) * ({{outhigh}} - {{outlow}}) / ({{inhigh}} - {{inlow}})",
    "smoothstep": {"expr": "mg_smoothstep({{in}}, {{low}}, {{high}})", "files": ["stdlib/adjustment/smoothstep.glsl"]},
    "luminance": {"expr": "mg_luminance({{in}}, {{lumacoeffs}})", "files": ["stdlib/adjustment/luminance.glsl"]},
    # hexcone colour model (Smith 1978); colour4 keeps its alpha
    "rgbtohsv": {"expr": "mg_rgbtohsv({{in}})", "files": ["stdlib/adjustment/rgbtohsv.glsl"]},
    "hsvtorgb": {"expr": "mg_hsvtorgb({{in}})", "files": ["stdlib/adjustment/hsvtorgb.glsl"]},
}
