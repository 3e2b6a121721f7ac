"""stdlib channel nodes (MaterialX Specification 1.39, "Channel Nodes").

separateN and most convert variants are nodegraphs in the data library (built from extract,
combine and constant), so only the leaves live here.
"""

NODES = {
    "extract": "{{in}}[{{=index}}]",
    "combine2": "{{$type}}({{in1}}, {{in2}})",
    "combine3": "{{$type}}({{in1}}, {{in2}}, {{in3}})",
    "combine4": "{{$type}}({{in1}}, {{in2}}, {{in3}}, {{in4}})",
    # the leaf converts: scalar casts
    "convert": "{{$type}}({{in}})",
}

NODEDEFS = {
    "ND_combine2_color4CF": "vec4({{in1}}, {{in2}})",
    "ND_combine2_vector4VF": "vec4({{in1}}, {{in2}})",
    "ND_combine2_vector4VV": "vec4({{in1}}, {{in2}})",
}
