"""MaterialX's own GenGlsl, used as the reference in tests and benchmarks (never in generation).

Needs the `materialx` wheel; raises ReferenceUnavailable with a clear message when it is missing.
"""
import os
import time


class ReferenceUnavailable(RuntimeError):
    pass


class MaterialXReference:
    def __init__(self, search_dirs=(), color_management=False, reduced=False):
        try:
            import MaterialX as mx
            import MaterialX.PyMaterialXGenGlsl as mx_glsl
            import MaterialX.PyMaterialXGenShader as mx_gen
        except ImportError as e:
            raise ReferenceUnavailable("the reference tests need the 'materialx' wheel (pip install materialx): %s"
                                       % e) from None
        self.mx, self.mx_gen, self.mx_glsl = mx, mx_gen, mx_glsl
        self.search = mx.FileSearchPath(os.path.dirname(mx.__file__))
        for d in search_dirs:
            self.search.append(d)
        self.lib = mx.createDocument()
        mx.loadLibraries(mx.getDefaultDataLibraryFolders(), self.search, self.lib)
        # MaterialX applies file colour spaces only with a colour management system registered (as its
        # viewer does); the bare generator, and so the scoreboard, reads every file as lin_rec709
        self.color_management = color_management
        # reduced: MaterialX's reduced shader interface (GenOptions.shaderInterfaceType =
        # SHADER_INTERFACE_REDUCED: unconnected inputs become constants), to compare with ours like with like
        self.reduced = reduced

    def load(self, path):
        doc = self.mx.createDocument()
        self.mx.readFromXmlFile(doc, path, self.search)
        doc.importLibrary(self.lib)
        return doc

    def elements(self, path):
        doc = self.load(path)
        return [e.getNamePath() for e in self.mx_gen.findRenderableElements(doc)]

    def generate(self, path, element, doc=None):
        """(vertex, fragment, {sampler: file}, seconds) of MaterialX's GLSL for one element."""
        doc = doc or self.load(path)
        gen = self.mx_glsl.GlslShaderGenerator.create()
        if self.color_management:
            cms = self.mx_gen.DefaultColorManagementSystem.create(gen.getTarget())
            cms.loadLibrary(self.lib)
            gen.setColorManagementSystem(cms)
        ctx = self.mx_gen.GenContext(gen)
        if self.reduced:
            ctx.getOptions().shaderInterfaceType = self.mx_gen.ShaderInterfaceType.SHADER_INTERFACE_REDUCED
        ctx.registerSourceCodeSearchPath(self.search)
        t = time.perf_counter()
        shader = gen.generate("s", doc.getDescendant(element), ctx)
        seconds = time.perf_counter() - t
        stage = shader.getStage(self.mx_gen.PIXEL_STAGE)
        textures = {}
        for block_name in stage.getUniformBlocks():
            block = stage.getUniformBlock(block_name)
            for i in range(block.size()):
                port = block[i]
                if port.getType().getName() == "filename" and port.getValue() is not None:
                    from mtlxgen.base.resolve import resolve_file
                    textures[port.getVariable()] = resolve_file(port.getValue().getValueString(), path) or ""
        return (shader.getSourceCode(self.mx_gen.VERTEX_STAGE), shader.getSourceCode(self.mx_gen.PIXEL_STAGE),
                textures, seconds)


def node_value(category, nodedef_name, inputs, types, out_type):
    """The value of one stdlib node (category, nodedef) of literal inputs, as a Python value: the tests' reference
    for what a node computes, and the function the generator folds constants with (fold.evaluate): one
    implementation. Raises fold.NotFoldable where the value is left to the GPU (undefined in GLSL)."""
    from mtlxgen.passes.fold import evaluate
    return evaluate(category, nodedef_name, inputs, types, out_type)
