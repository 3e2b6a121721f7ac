"""The shader interface of an element: which of its public inputs stay uniforms.

complete (the default): every public input is a uniform named as MaterialX names it, initialised with its value;
what `generate` has always written.

reduced: every input that is not connected and not kept editable becomes a literal in the code. An input stays a
uniform where
  - the document marks it `uniform="true"` (on the input or on its nodedef's input: graph.Uniform.marked),
  - it is named by `--keep NAME` or in a `--keep-file FILE` (one name a line, or a JSON list of names, or a manifest
    this program wrote: its "kept", else its "uniforms"' names),
  - it cannot be a literal: a texture (sampler), an array or a struct value.
A NAME is a uniform's name as the complete manifest lists it (`SR_default_base_color`), or `NODE/INPUT`
(`SR_default/base_color`, also `NODE.INPUT`) which names the same uniform. The application uniforms (matrices, view
position, environment, lights) are not the material's inputs: they are always uniforms, but for progressive
refinement's pair (interface.PROGRESSIVE: frame k of K), which a reduced shader reads as constants at their defaults
(one frame's estimate) unless a kept name is either of them.

reduce() is a graph pass: a Graph in, a new Graph out (the input graph is never changed); fold.py then evaluates what
became constant.
"""
import json
import re
from mtlxgen.base.records import dataclass, field, replace

from mtlxgen.base import interface as app_interface
from mtlxgen.base.diagnostics import Loc, MtlxError
from mtlxgen.graph.build import Source, glsl_identifier

INTERFACES = ("complete", "reduced")

# types a literal can carry in place of a uniform (arrays, structs and samplers stay uniforms)
LITERAL_TYPES = ("float", "integer", "boolean", "color3", "color4", "vector2", "vector3", "vector4",
                 "matrix33", "matrix44")


@dataclass
class Interface:
    """How an element's public inputs are exposed. keep: [(name, Loc or None)]: Loc where a --keep-file line
    names it, None for a --keep option. matched: the names that named an input of some element generated (a name
    matching nothing is an error: unmatched())."""
    kind: str = "complete"
    keep: list = field(default_factory=list)
    matched: set = field(default_factory=set)

    def __post_init__(self):
        if self.kind not in INTERFACES:
            raise ValueError("interface must be one of %s, not %r" % (", ".join(INTERFACES), self.kind))

    @property
    def reduced(self):
        return self.kind == "reduced"

    def unmatched(self, doc_path):
        """(Loc, message) for each kept name that named no public input of the elements generated."""
        out = []
        for name, loc in self.keep:
            if name in self.matched:
                continue
            if loc is None:
                out.append((Loc(doc_path, 0), "--keep %r: no public input of the elements generated is named so "
                                              "(a uniform name as the complete manifest lists it, or NODE/INPUT)"
                            % name))
            else:
                out.append((loc, "%r: no public input of the elements generated from %s is named so (a uniform name "
                                 "as the complete manifest lists it, or NODE/INPUT)" % (name, doc_path)))
        return out


def interface(kind="complete", keep=(), keep_file=None):
    """An Interface from the options: --interface KIND, --keep NAME ... and --keep-file FILE. Keeping names is
    for the reduced interface (every input is a uniform in the complete one): with complete they are an error."""
    if (keep or keep_file) and kind != "reduced":
        raise ValueError("--keep and --keep-file name inputs kept editable in the reduced interface: "
                         "add --interface reduced")
    names = [(n, None) for n in keep]
    if keep_file:
        names += read_keep_file(keep_file)
    return Interface(kind, names)


def read_keep_file(path):
    """[(name, Loc)] of a keep file: a JSON list of names, a JSON manifest of ours ("kept", else "uniforms"' names),
    or one name a line (blank lines and lines starting with '#' skipped)."""
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read(1 << 20)
    except (OSError, UnicodeDecodeError) as e:
        raise MtlxError((Loc(path, 0), "cannot read the keep file: %s" % (getattr(e, "strerror", None) or e)))
    stripped = text.lstrip()
    if stripped[:1] in ("[", "{"):
        try:
            data = json.loads(text)
        except ValueError as e:
            raise MtlxError((Loc(path, getattr(e, "lineno", 0)), "not a JSON list of names: %s" % e.msg)) from None
        except RecursionError:
            raise MtlxError((Loc(path, 1), "not a JSON list of names: nested too deeply")) from None
        if isinstance(data, dict) and "kept" in data:
            data = data["kept"]
        elif isinstance(data, dict) and isinstance(data.get("uniforms", []), list):
            data = [u.get("name") if isinstance(u, dict) else u for u in data.get("uniforms", [])]
        if not isinstance(data, list):
            raise MtlxError((Loc(path, 1), "a JSON keep file is a list of names (or a manifest with \"uniforms\")"))
        out = []
        for item in data:
            if not isinstance(item, str) or not item.strip():
                raise MtlxError((Loc(path, _line_of(text, json.dumps(item))), "not a name: %s" % json.dumps(item)))
            out.append((item.strip(), Loc(path, _line_of(text, json.dumps(item)))))
        return out
    out = []
    for i, line in enumerate(text.splitlines(), 1):
        s = line.strip()
        if s and not s.startswith("#"):
            out.append((s, Loc(path, i)))
    return out


def _line_of(text, needle):
    k = text.find(needle)
    return text.count("\n", 0, k) + 1 if k >= 0 else 1


def uniform_names(name):
    """The uniform names a kept NAME can mean: itself, and NODE/INPUT or NODE.INPUT as the graph names it."""
    out = {name}
    if "/" in name or "." in name:
        out.add(glsl_identifier(re.sub(r"[/.]", "_", name)))
    return out


def reduce(graph, iface):
    """(the Graph with the reduced interface, [names of the uniforms kept]). Records in iface.matched the kept
    names that named one of this graph's inputs."""
    wanted = {}
    for name, _ in iface.keep:
        for u in uniform_names(name):
            wanted.setdefault(u, []).append(name)
    progressive = [name for name in wanted if name in app_interface.PROGRESSIVE]
    for name in progressive:                # names of the application interface: they always name something
        iface.matched.update(wanted[name])
    literal, kept = {}, []
    for name, u in graph.uniforms.items():
        if name in wanted:
            iface.matched.update(wanted[name])
            kept.append(name)
        elif getattr(u, "marked", False) or u.type not in LITERAL_TYPES or u.value is None:
            kept.append(name)
        else:
            literal[name] = u

    def lit(s):
        if s.uniform is None or s.uniform not in literal:
            return s
        return Source(s.type, value=literal[s.uniform].value, loc=s.loc, unit=s.unit, unittype=s.unittype)

    nodes = [replace(n, inputs={k: lit(s) for k, s in n.inputs.items()}, outputs=dict(n.outputs),
                     static=dict(n.static)) for n in graph.nodes]
    uniforms = {k: replace(u) for k, u in graph.uniforms.items() if k not in literal}
    constants = frozenset() if progressive else frozenset(app_interface.PROGRESSIVE)
    return replace(graph, nodes=nodes, uniforms=uniforms, result=lit(graph.result), warnings=list(graph.warnings),
                   app_constants=constants), kept
