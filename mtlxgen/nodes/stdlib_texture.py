"""stdlib texture nodes (MaterialX Specification 1.39, "Texture Nodes" and "Convolution Nodes"), plus
normalmap, whose encoded input usually comes from an image.

image reads its file through a sampler uniform. Address modes, filtertype and the `default` colour are
sampler state, as in MaterialX's own GLSL: they go into the file's texture entry of the interface
manifest (interface.md) for the application to apply (GL wrap / border colour / filter), and an
application binds a 1x1 texture of `default` when the file cannot be read (draw/renderer.py does).
The file's colour space is converted to lin_rec709 in GLSL right after the read (cmlib.py).
Files naming `<UDIM>` or `<UVTILE>` get one sampler per tile found on disk (handlers.image).
tiledimage, triplanarprojection, latlongimage, blur and bump are nodegraphs in the data libraries.
"""

NODES = {
    "image": {"handler": "image"},
    "hextiledimage": {"handler": "hextiledimage"},
    "hextilednormalmap": {"handler": "hextiledimage"},
    "normalmap": {"expr": "mg_normalmap({{in}}, {{scale}}, {{normal}}, {{tangent}}, {{bitangent}})",
                  "files": ["stdlib/texture/normalmap.glsl"]},
    "heighttonormal": {"expr": "mg_heighttonormal({{in}}, {{scale}}, {{texcoord}})",
                       "files": ["stdlib/texture/heighttonormal.glsl"]},
}
