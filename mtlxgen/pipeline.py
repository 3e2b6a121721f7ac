"""The whole pipeline for one document: read, resolve, build each element's graph, emit GLSL."""
import copy
import os

from mtlxgen.read import library
from mtlxgen.emit import emitter as emit
from mtlxgen.graph import functions, build as graph
from mtlxgen.draw import glslcheck
from mtlxgen import nodes
from mtlxgen.passes import order as passes
from mtlxgen.base.diagnostics import Loc, MtlxError, Problems, Warnings, strict_error, warning_lines
from mtlxgen.options import GenerateOptions
from mtlxgen.graph.transparency import transparent_surface
from mtlxgen.read.source import load_document  # noqa: F401 (pipeline.load_document)
from mtlxgen.read.xmlreader import gc_paused


def graph_rules(usd_seed_rules=False):
    """The graph.BuildRules graph building works under: the GLSL target's (nodes.RULES), with USD's seed
    rules on top where they are on (nodes/usd.py)."""
    if usd_seed_rules:
        from mtlxgen.nodes.usd import SeedRules
        return SeedRules(nodes.RULES)
    return nodes.RULES


def build_graph(doc, lib, element, usd_seed_rules=False, warnings=None):
    """graph.build_graph under the GLSL target's rules (graph_rules)."""
    return graph.build_graph(doc, lib, element, graph_rules(usd_seed_rules), warnings)


class Session:
    """A document opened for generation: the libraries with the document's own definitions, the
    elements to draw, and whether USD's seed rules apply. Build its elements with graph() / shader().

    options: how shaders are generated (options.GenerateOptions; None: the defaults), with `settings`
    (GenerateOptions fields as keywords) on top. elements: the element names (or a USD stage's material prim
    paths) to draw; None: every renderable element.

    Warnings (slips MaterialX reads on, read as it reads them) go to `warnings` (a diagnostics.Warnings, the
    caller's if given) as they are met: the document's own when it is read, each element's when it is built.
    options.strict: a warning is an error instead: a document with warnings of its own raises here, an element with
    warnings raises where it is built (nothing of it written)."""

    def __init__(self, path, options=None, elements=None, warnings=None, **settings):
        self.path = path
        self.options = options = GenerateOptions.of(options, **settings)
        self.max_lights = options.max_lights
        self.interface = options.make_interface()       # its own: it records which kept names matched
        self.environment = options.environment
        self.target = options.target
        self.strict = strict = options.strict
        self.warnings = warnings if warnings is not None else Warnings()
        self.element_warnings = {}          # element name -> [(Loc, message)] met building it
        self.element_notes = {}             # element name -> [(Loc, message)]: its textures that cannot be read
        self.unreadable = {}                # element name -> {sampler uniform}: those textures' uniforms
        self.texture_inputs = {}            # element name -> {sampler uniform: Loc of the input naming its file}
        try:
            self.doc = load_document(path, options.library_dirs, options.stage_options(path))
        except MtlxError as e:          # the document's warnings too, met before its problems
            if strict and e.warnings:
                raise MtlxError(strict_error(e.warnings).problems + e.problems) from None
            self.warnings.extend(e.warnings)
            raise
        self.doc_warnings = list(getattr(self.doc, "warnings", ()))
        if strict and self.doc_warnings:
            raise strict_error(self.doc_warnings)
        self.warnings.extend(self.doc_warnings)
        if library._materialx_library_root() is None:       # MaterialX's nodedefs come with its wheel
            raise ModuleNotFoundError("No module named 'MaterialX' (pip install materialx): its data libraries "
                                      "define the standard nodes", name="MaterialX")
        self.library = library.load_library(options.library_dirs).overlay(self.doc)   # once per document
        self.stage = getattr(self.doc, "usd", None)     # usdstage.StageInfo for a USD stage
        if self.stage is not None and elements:          # elements named by prim path too
            elements = [self.stage.element_for(e) for e in elements]
        self.elements = list(elements or graph.renderable_elements(self.doc))
        usd_seed_rules = options.usd_seed_rules
        if usd_seed_rules is None:
            from mtlxgen.nodes.usd import comes_from_usd
            usd_seed_rules = comes_from_usd(self.doc)
        self.usd_seed_rules = usd_seed_rules
        self.rules = graph_rules(usd_seed_rules)     # what the target tells graph building
        if not self.elements:
            raise MtlxError((Loc(path, 1), "nothing to render: no material, shader or output elements"))

    def graph(self, name, functions=False):
        """Element `name`'s Graph; functions: nodegraph implementations as call nodes where they can be
        (functions.py: the complete interface's shaders), else expanded in place."""
        if self.stage is not None and name in self.stage.materials and self.stage.materials[name].problems:
            raise MtlxError(self.stage.materials[name].problems)      # what the stage reader could not convert
        found = []
        try:
            g = graph.build_graph(self.doc, self.library, name, self.rules, warnings=found, functions=functions)
        finally:
            self.element_warnings[name] = found
            if not self.strict:             # strict: they are errors, raised below
                self.warnings.extend(found)
        if self.strict and found:
            raise strict_error(found)
        self.texture_inputs[name] = {u.name: u.loc for u in g.uniforms.values()
                                     if u.type == "filename" and u.loc is not None}
        if self.stage is None:              # a stage's textures are checked as the stage is read (usdstage.py)
            found = texture_notes(g, self.path)
            self.element_notes[name] = [(loc, message) for _, loc, message in found]
            self.unreadable[name] = {uniform for uniform, _, _ in found}
        return g

    def warning_lines(self, name):
        """`FILE:LINE: warning: ...` lines of the document's warnings and those met building element `name`."""
        return warning_lines(self.doc_warnings + [w for w in self.element_warnings.get(name, ())
                                                  if w not in self.doc_warnings])

    def shader(self, name, interface=None, graph=None):
        """Element `name`'s Shader, with the session's interface or `interface` (a reduce.Interface), from its graph
        or `graph` (this session's graph(name, ...), already built: not built again). The complete interface calls
        nodegraph implementations as functions (functions.py); the reduced one expands them, to fold their constants."""
        iface = interface or self.interface
        if graph is None:                   # the build pass
            graph = self.graph(name, functions=not iface.reduced)
        ir, kept = passes.run(graph, iface)     # the later passes, in order (passes/order.py)
        try:
            shader = self._emit(ir, iface)
        except functions.Inline:            # a compile-time input connected: expanded in place instead
            shader = self._emit(passes.run(self.graph(name), iface)[0], iface)
        return self.finish(name, shader, iface, kept)

    def _emit(self, g, iface):
        return glslcheck.check(emit.emit(g, environment=self.environment, target=self.target,
                                         max_lights=self.max_lights, compact=iface.reduced))

    def finish(self, name, shader, interface=None, kept=None):
        """`shader` with what the session adds to an element's manifest."""
        shader.manifest["interface"] = (interface or self.interface).kind
        shader.manifest["transparent"] = transparent_surface(self.doc, self.library, name)
        if kept is not None:
            shader.manifest["kept"] = kept
        if self.stage is not None and name in self.stage.materials:
            shader.manifest["usd"] = self.stage.manifest(name)
        return shader

    def drawable(self, name, shader):
        """`shader` as whatever draws it binds it: a texture file that cannot be read (notes()) left out of its
        manifest, so the image's default is drawn and nothing opens the file (a FIFO, a device); and where each
        file it binds is named (Shader.texture_inputs: a file that does not decode is reported there, at_inputs)."""
        if not shader.manifest.get("textures"):
            return shader
        if name not in self.texture_inputs:         # a shader made from a graph not built here
            self.graph(name)
        inputs, left_out = self.texture_inputs[name], self.unreadable.get(name, ())
        shader = copy.copy(shader)
        shader.manifest = dict(shader.manifest, textures=[
            dict(t, file="") if t.get("uniform") in left_out else t for t in shader.manifest["textures"]])
        shader.texture_inputs = {t["file"]: inputs[t["uniform"]] for t in shader.manifest["textures"]
                                 if t.get("file") and t.get("uniform") in inputs}
        return shader

    def notes(self, name=None):
        """Problems that leave an element drawn (a texture not found: its default or fallback is drawn); with no
        name, those of the stage as a whole. For a .mtlx document, those of an element already built (graph())."""
        if self.stage is None:
            if name is None:
                return []
            return list(self.element_notes.get(name, ()))
        if name is None:
            return list(self.stage.problems)
        m = self.stage.materials.get(name)
        return list(m.notes) if m is not None else []


def texture_problem(value, doc_path):
    """Why the texture file a filename value names cannot be read (a message naming it), or None: none named,
    found and a regular file within the image cap, or a tile pattern (emission finds tiles and refuses a
    pattern without any: emit/emitter.py)."""
    from mtlxgen.base.files import quoted, regular_file_problem
    from mtlxgen.base.resolve import resolve_file
    if not isinstance(value, str) or not value.strip() or "<UDIM>" in value or "<UVTILE>" in value:
        return None
    found = resolve_file(value, doc_path)
    if found is None:
        looked = value if os.path.isabs(value) else os.path.join(os.path.dirname(os.path.abspath(doc_path)), value)
        return ("texture %s not found (looked for %s and in the search paths); the image's default is drawn"
                % (quoted(value), looked))
    why = regular_file_problem(found, "image")
    return None if why is None else "texture %s is %s; the image's default is drawn" % (quoted(value), why)


def texture_notes(g, doc_path):
    """[(uniform, Loc, message)] for each texture file of graph `g` (a .mtlx document's) that cannot be read
    (texture_problem). The shader is valid all the same (the image node's default is drawn), so generate reports
    them as warnings and everything that draws as problems."""
    notes = []
    for u in g.uniforms.values():
        why = texture_problem(u.value, doc_path) if u.type == "filename" else None
        if why is not None:
            notes.append((u.name, u.loc or Loc(doc_path, 0), why))
    return notes


def at_inputs(shader, error):
    """`error` (an MtlxError from drawing `shader`) with each problem about one of its texture files (reported at
    FILE:0 by the image reader, FILE:LINE by the IES reader) moved to the document input naming that file
    (Shader.texture_inputs, set by Session.drawable): one line naming the input and the texture."""
    from mtlxgen.base.files import quoted
    where = getattr(shader, "texture_inputs", None) or {}
    moved = []
    for loc, message in error.problems:
        if loc.where is None and loc.file in where:
            at = " line %d" % loc.line if loc.line else ""
            moved.append((where[loc.file], "texture %s%s: %s" % (quoted(loc.file), at, message)))
        else:
            moved.append((loc, message))
    return MtlxError(moved, error.warnings)


@gc_paused()       # hundreds of thousands of objects, no cycles: the collector only slows a large graph 2-3x
def generate(path, options=None, elements=None, partial=False, warnings=None, **settings):
    """Shaders for the renderable elements of a .mtlx file or USD stage (or the named ones).

    options: an options.GenerateOptions (None: the defaults), with `settings` (its fields as keywords:
    target="essl", max_lights=2, ...) on top. What they mean is told there; a kept name (options.keep) that names
    no input of the elements generated is a problem, and so is a texture file that cannot be read where
    options.unreadable_textures is "error" (for whatever draws the shader, which would show a wrong image:
    render, view, web, three, golden and batch); as a "warning" (the default) it is a warning, an error all the
    same under strict.

    warnings: a diagnostics.Warnings that receives every warning met (Session).

    Returns [Shader]. Problems in any element are collected and raised together as one MtlxError;
    with partial=True returns (shaders that worked, MtlxError or None) instead.
    """
    session = Session(path, options, elements, warnings, **settings)
    options = session.options
    unreadable_textures, strict = options.unreadable_textures, options.strict
    problems, shaders = Problems(), []
    as_warnings = unreadable_textures == "warning" and not strict

    def note(items):
        if as_warnings:
            session.warnings.extend(items)
        elif unreadable_textures == "warning":          # strict
            problems.extend(strict_error(items))
        else:
            for loc, message in items:
                problems.add(loc, message)
    for loc, message in session.notes():    # the stage's own (a variant it lacks, composition): always problems
        problems.add(loc, message)
    for name in session.elements:
        try:
            shader = session.shader(name)
            shaders.append(session.drawable(name, shader) if unreadable_textures == "error" else shader)
        except MtlxError as e:
            problems.extend(e)
        note(session.notes(name))
    if shaders:                         # a name kept (--keep) that named nothing drawn
        for loc, message in session.interface.unmatched(path):
            problems.add(loc, message)
    emit.unique_stems(shaders)          # one output folder holds them all
    if partial:
        return shaders, (MtlxError(problems.items) if problems else None)
    problems.raise_if_any()
    return shaders

