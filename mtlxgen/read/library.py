"""Data libraries: find them, load their nodedefs and nodegraph implementations, index them.

Sources, in order: the `materialx` wheel's MaterialX/libraries (stdlib, pbrlib, bxdf, cmlib, lights,
nprlib; never its gen* folders: we read definitions, not MaterialX's shader code), mtlxgen's own
library (glsl_lib/*.mtlx), directories in MATERIALX_SEARCH_PATH, and directories given with --library.
Parsed libraries are cached in a compact file (library_cache.py: keyed by every file's path, size and mtime and
by the code that reads them; checked before it is read; its entries decoded only when first used) so that a warm
load takes a few milliseconds. Nodedefs are found by (category, version, type, input signature), memoized
(Library.find_nodedef), not by scanning a category's list for every node.
"""
import functools
import os
import re
from mtlxgen.base.records import dataclass, field

from mtlxgen.base.diagnostics import MtlxError
from mtlxgen.base.files import glsl_lib_root, materialx_library_root  # noqa: F401 (library.X for callers)

LIBRARY_FOLDERS = ("stdlib", "pbrlib", "bxdf", "cmlib", "lights", "nprlib")


# GLSL 4.00's built-in functions (spec chapter 8): a struct of the same name would hide them
GLSL_BUILTIN_FUNCTIONS = frozenset("""radians degrees sin cos tan asin acos atan sinh cosh tanh asinh acosh atanh
pow exp log exp2 log2 sqrt inversesqrt abs sign floor trunc round roundEven ceil fract mod modf min max clamp mix
step smoothstep isnan isinf floatBitsToInt floatBitsToUint intBitsToFloat uintBitsToFloat fma frexp ldexp
packUnorm2x16 packSnorm2x16 packUnorm4x8 packSnorm4x8 unpackUnorm2x16 unpackSnorm2x16 unpackUnorm4x8
unpackSnorm4x8 packDouble2x32 unpackDouble2x32 packHalf2x16 unpackHalf2x16 length distance dot cross normalize
ftransform faceforward reflect refract matrixCompMult outerProduct transpose determinant inverse lessThan
lessThanEqual greaterThan greaterThanEqual equal notEqual any all not uaddCarry usubBorrow umulExtended
imulExtended bitfieldExtract bitfieldInsert bitfieldReverse bitCount findLSB findMSB textureSize textureQueryLod
texture textureProj textureLod textureOffset texelFetch texelFetchOffset textureProjOffset textureLodOffset
textureProjLod textureProjLodOffset textureGrad textureGradOffset textureProjGrad textureProjGradOffset
textureGather textureGatherOffset textureGatherOffsets dFdx dFdy fwidth interpolateAtCentroid
interpolateAtSample interpolateAtOffset noise1 noise2 noise3 noise4 EmitStreamVertex EndStreamPrimitive
EmitVertex EndPrimitive barrier""".split())


_MTLXGEN_PREFIX = re.compile(r"mg_|MG_|Mg[A-Z]")     # mtlxgen's own names in generated GLSL


@functools.lru_cache(maxsize=None)
def glsl_lib_names():
    """Global names of mtlxgen's GLSL library (structs, functions, constants, macros) and GLSL's built-in
    functions: a document's struct type taking one would clash with it or hide it."""
    texts = []
    for dp, _, fs in os.walk(glsl_lib_root()):
        texts += [_read_text(os.path.join(dp, f)) for f in fs if f.endswith(".glsl")]
    code = re.sub(r"//[^\n]*|/\*.*?\*/", " ", "\n".join(texts), flags=re.S)
    found = re.findall(r"\bstruct\s+(\w+)|#\s*define\s+(\w+)|\bconst\s+\w+\s+(\w+)|^\s*\w+\s+(\w+)\s*\(",
                       code, flags=re.M)
    from mtlxgen.base.interface import LIGHT_STRUCT_NAMES, TABLE
    return frozenset(n for groups in found for n in groups if n) | GLSL_BUILTIN_FUNCTIONS | frozenset(TABLE) | \
        LIGHT_STRUCT_NAMES


def _read_text(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


# _mtlx_files' walks: (root, folders) -> ([(folder, mtime)] of every folder walked, files). A folder's mtime changes
# when a file is added to it, removed or renamed: a walk whose folders are all unchanged lists the same files, and
# checking that takes a stat per folder, not a walk (load_library runs for every document generated).
_WALKS = {}


def _folder_mtime(path):
    try:
        return os.stat(path).st_mtime_ns
    except OSError:
        return None


def _mtlx_files(root, folders=None):
    key = (root, tuple(folders) if folders else None)
    walked = _WALKS.get(key)
    if walked is not None and all(_folder_mtime(d) == m for d, m in walked[0]):
        return list(walked[1])
    out, seen = [], []
    tops = [os.path.join(root, f) for f in folders] if folders else [root]
    for top in tops:
        seen.append((top, _folder_mtime(top)))      # (also a top that is not there: made later, it is seen)
        for dp, dns, fs in os.walk(top):
            if dp != top:
                seen.append((dp, _folder_mtime(dp)))
            dns[:] = sorted(d for d in dns if not d.startswith("gen") and d != "targets")
            out.extend(os.path.join(dp, f) for f in sorted(fs) if f.endswith(".mtlx"))
    _WALKS[key] = (seen, tuple(out))
    return out


@functools.lru_cache(maxsize=None)
def _materialx_library_root():
    """files.materialx_library_root, looked up once per process (the installed wheel does not move)."""
    return materialx_library_root()


def library_files(extra_dirs=()):
    files = []
    mx_root = _materialx_library_root()
    if mx_root:
        files += _mtlx_files(mx_root, LIBRARY_FOLDERS)
    files += _mtlx_files(glsl_lib_root())
    env = os.environ.get("MATERIALX_SEARCH_PATH", "")
    for d in [p for p in env.split(os.pathsep) if p] + list(extra_dirs):
        if os.path.isdir(d):
            files += _mtlx_files(d)
        elif os.path.isfile(d):
            files.append(d)
    seen, unique = set(), []
    for f in files:
        a = os.path.abspath(f)
        if a not in seen:
            seen.add(a)
            unique.append(a)
    return unique


@dataclass
class Library:
    nodedefs: dict = field(default_factory=dict)        # name -> NodeDef (inheritance flattened)
    by_category: dict = field(default_factory=dict)     # category -> [NodeDef] in load order
    graph_impls: dict = field(default_factory=dict)     # nodedef name -> NodeGraph implementing it
    nodegraphs: dict = field(default_factory=dict)      # every library nodegraph by name
    implementations: dict = field(default_factory=dict)  # nodedef name -> Implementation (genglsl / untargeted)
    geompropdefs: dict = field(default_factory=dict)
    unitdefs: dict = field(default_factory=dict)
    structs: dict = field(default_factory=dict)
    files: list = field(default_factory=list)
    # find_nodedef's memos: (category, version, type) -> candidates, signature -> nodedef; cleared on any change
    _candidates: dict = field(default_factory=dict, init=False, repr=False, compare=False)
    _matches: dict = field(default_factory=dict, init=False, repr=False, compare=False)
    # functions.py's nodegraph implementations as GLSL functions, by key (functions.Family): cleared on any change
    functions: dict = field(default_factory=dict, init=False, repr=False, compare=False)
    # graph building's geometric-property nodes, by geompropdef name (build.GraphBuilder.geom_source): cleared too
    geom_nodes: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def find_nodedef(self, category, version, node_type, inputs):
        """The nodedef a node of `category` (its `version`, output `node_type` and `inputs`, a dict of ports)
        resolves to: the first of the category's nodedefs, in library order, that the version rule admits,
        whose output type matches, and that declares every input the node has with the node's type; None
        where none does (graph.GraphBuilder.nodedef_for then says why). Memoized by signature: a document of
        100,000 nodes of a few kinds matches a few times, not once a node."""
        key = (category, version, node_type, tuple([(p.name, p.type) for p in inputs.values()]))
        try:
            return self._matches[key]
        except KeyError:
            pass
        ckey = key[:3]
        candidates = self._candidates.get(ckey)
        if candidates is None:
            candidates = self._candidates[ckey] = self._admitted(category, version, node_type)
        found = None
        for nd, nd_inputs in candidates:
            for name, type_name in key[3]:
                decl = nd_inputs.get(name)
                if decl is None or decl.type != type_name:
                    break
            else:
                found = nd
                break
        self._matches[key] = found
        return found

    def _admitted(self, category, version, node_type):
        """[(nodedef, its inputs)] of `category` that a node of this version and output type may resolve to, in
        library order. Versions: a node naming one takes only nodedefs of that version; a node naming none
        skips versioned nodedefs that are not the default where the category has an unversioned or a default one."""
        candidates = self.by_category.get(category) or []
        plain = sum(1 for o in candidates if o.version is None or o.isdefaultversion)
        out = []
        for nd in candidates:
            if version:
                if nd.version != version:
                    continue
            elif nd.version and not nd.isdefaultversion and plain:
                continue
            if len(nd.outputs) > 1:
                if node_type not in ("multioutput", ""):
                    continue
            elif nd.type != node_type:
                continue
            out.append((nd, nd.inputs))
        return out

    def _changed(self):
        self._candidates.clear()
        self._matches.clear()
        self.functions.clear()
        self.geom_nodes.clear()

    def add_document(self, doc, overlay=False):
        self._changed()
        taken = [st for st in doc.structs.values() if st.name in glsl_lib_names() or _MTLXGEN_PREFIX.match(st.name)]
        if taken:
            raise MtlxError([(st.loc, "typedef '%s': the generated GLSL already uses the name '%s'"
                              % (st.name, st.name)) for st in taken])
        self.structs.update(doc.structs)
        self.geompropdefs.update(doc.geompropdefs)
        for unittype, units in doc.unitdefs.items():
            self.unitdefs.setdefault(unittype, {}).update(units)
        for nd in doc.nodedefs.values():
            if nd.name in self.nodedefs:
                old = self.nodedefs[nd.name]
                self.by_category[old.category] = [d for d in self.by_category[old.category] if d.name != nd.name]
            self.nodedefs[nd.name] = nd
            lst = self.by_category.setdefault(nd.category, [])
            if overlay:
                lst.insert(0, nd)       # a document's own definitions win over the library's
            else:
                lst.append(nd)
        for g in doc.nodegraphs.values():
            self.nodegraphs[g.name] = g
            # a document graph claiming a library nodedef that already has an implementation keeps
            # the library's (the graph still renders on its own)
            if g.nodedef and not (overlay and g.nodedef not in doc.nodedefs and g.nodedef in self.nodedefs):
                self.graph_impls[g.nodedef] = g
        for impl in doc.implementations.values():
            if impl.target not in (None, "", "genglsl"):
                continue
            if impl.nodedef:
                if impl.nodegraph and impl.nodegraph in self.nodegraphs:
                    self.graph_impls[impl.nodedef] = self.nodegraphs[impl.nodegraph]
                else:
                    self.implementations[impl.nodedef] = impl

    def flatten_inheritance(self):
        self._changed()
        # a cached library's nodedefs are flattened already: only those added since (an overlay's) are walked
        loaded = getattr(self.nodedefs, "loaded_values", None)
        for nd in (loaded() if loaded else self.nodedefs.values()):
            chain, cur, seen = [], nd, set()
            while cur.inherit and cur.inherit in self.nodedefs and cur.inherit not in seen:
                seen.add(cur.inherit)
                cur = self.nodedefs[cur.inherit]
                chain.append(cur)
            for parent in chain:
                merged = dict(parent.inputs)
                merged.update(nd.inputs)
                nd.inputs = merged
                for k, v in parent.outputs.items():
                    nd.outputs.setdefault(k, v)
            nd.inherit = None

    def overlay(self, doc):
        """A new Library: this one plus the definitions a document declares itself (this one when it
        already is that overlay)."""
        if getattr(self, "overlaid", None) is doc or getattr(self, "_plain", None) is doc:
            return self
        if not (doc.nodedefs or doc.implementations or doc.structs or doc.unitdefs or doc.geompropdefs
                or any(g.nodedef for g in doc.nodegraphs.values())):
            self._plain = doc           # (the last document found to define nothing: each element asks again)
            return self
        lib = Library(nodedefs=_copy(self.nodedefs), by_category=_copy(self.by_category, list),
                      graph_impls=_copy(self.graph_impls), nodegraphs=_copy(self.nodegraphs),
                      implementations=dict(self.implementations), geompropdefs=dict(self.geompropdefs),
                      unitdefs={k: dict(v) for k, v in self.unitdefs.items()}, structs=dict(self.structs),
                      files=self.files)
        lib.add_document(doc, overlay=True)
        lib.flatten_inheritance()
        lib.overlaid = doc
        return lib


def _copy(table, each=None):
    """A copy of one of a Library's tables (a dict, or library_cache's lazy table: what it has not decoded
    stays undecoded); `each` copies every value too."""
    if not isinstance(table, dict):
        return table.copy(each)
    return {k: each(v) for k, v in table.items()} if each else dict(table)


def _source_of(path):
    parts = os.path.normpath(path).split(os.sep)
    for f in LIBRARY_FOLDERS:
        if f in parts:
            return f
    return "mtlxgen" if "glsl_lib" in parts else "user"


def parse_library(files):
    """A Library read from its files (no cache)."""
    from mtlxgen.read import document
    lib = Library(files=files)
    for path in files:
        lib.add_document(document.load(path, source=_source_of(path)))
    lib.flatten_inheritance()
    return lib


_MEMO = {}


def load_library(extra_dirs=(), use_cache=True):
    """Load every data library (memoized per process; from the compact cache where it holds these files as
    they are now). Raises MtlxError if a library file is broken."""
    files = library_files(extra_dirs)
    if not files:
        raise MtlxError((None, "no MaterialX data libraries found: install the 'materialx' wheel or set "
                               "MATERIALX_SEARCH_PATH"))
    key = tuple(files)
    if key in _MEMO:
        return _MEMO[key]
    if not use_cache:
        lib = parse_library(files)
    else:
        from mtlxgen.read import library_cache
        lib = library_cache.load(files, parse_library, Library)
    _MEMO[key] = lib
    return lib
