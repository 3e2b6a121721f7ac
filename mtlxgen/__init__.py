"""mtlxgen: MaterialX documents to GLSL shaders.

The pipeline, one module a stage, plain data between them:

    xmlreader  .mtlx text         -> element tree with file/line      (xml + xi:include)
    document   element tree       -> Document of typed dataclasses    (values parsed, prefixes applied)
    library    data libraries     -> Library: nodedefs indexed by category and signature
    graph      Document + Library -> Graph: resolved, type-checked, flattened, ordered nodes
    emit       Graph              -> Shader: vertex and fragment GLSL plus interface manifest
    render     Shader             -> linear RGBA pixels (moderngl, headless)

    view       a document, live   -> a window redrawn as the files change (render's drawing path, hot reload,
                                     progressive sampling, property panel: geometry, docedit, viewpanel)
"""
__version__ = "0.1.0"
