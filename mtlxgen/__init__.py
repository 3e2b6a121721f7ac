"""mtlxgen: MaterialX documents to GLSL shaders.

The pipeline, one module a stage, plain data between them:

    xmlreader  .mtlx text         -> element tree with file/line      (xml + xi:include)
    document   element tree       -> Document of typed dataclasses    (values parsed, prefixes applied)
    library    data libraries     -> Library: nodedefs indexed by category and signature
    graph      Document + Library -> Graph: resolved, type-checked, flattened, ordered nodes
                                     (graphtypes: the Graph's data and naming rules; the target's
                                     graph.BuildRules handed in by pipeline: nodes.RULES, nodes/usd.SeedRules)
    emit       Graph              -> Shader: vertex and fragment GLSL plus interface manifest
                                     (closureplan: when closures are needed; template: inline templates;
                                     stagewriter: main's lines; nodes/: the node table and pure handlers)
    render     Shader             -> linear RGBA pixels (moderngl, headless)

    view       a document, live   -> a window redrawn as the files change (render's drawing path, hot reload,
                                     progressive sampling, property panel: geometry, docedit, viewpanel)
"""
__version__ = "0.1.0"

# usdstage.USD_EXTENSIONS, here so that telling a USD stage from a .mtlx document imports nothing (usdstage's
# import costs a small generation's time); tests/test_library_index.py holds them equal
USD_EXTENSIONS = (".usd", ".usda", ".usdc", ".usdz")


def is_usd(path):
    """Whether `path` names a USD stage (by its extension), as usdstage.is_usd says."""
    return str(path).lower().endswith(USD_EXTENSIONS)
