"""Plain data classes: the part of the standard library's `dataclasses` that mtlxgen uses, at a fraction of its
start-up cost.

Every record of the pipeline (a document's Port and Node, the graph's Source and GNode, a Shader, the options) is
declared as a data class: annotated fields with defaults, `field(default_factory=...)`, `frozen`, `slots`,
`eq=False`, `__post_init__`, `fields()`, `replace()` and `asdict()`. The standard module costs every command
35-40 ms before it does any work: importing it imports `inspect` (8-11 ms), and it compiles each generated method
of each class by itself (25 classes on the path to a written shader: 25-30 ms), a quarter of a cold `mtlxgen
generate` (docs/measuring.md). This module imports nothing, writes `__repr__` and the frozen records'
`__setattr__` as plain functions, and compiles a class's `__init__`, `__eq__` and `__hash__` each when it is first
called (a command uses a few of the methods of the records it imports): 1.5 ms for the 25 classes.

What it supports is exactly that subset, with the standard module's meaning (tests/base/test_records.py holds them
side by side): `__init__` with the fields in order (a default, or a factory called per instance; `init=False`
fields set from theirs), `__repr__` of the `repr` fields, `__eq__` of the `compare` fields between instances of one
class, `__hash__` of them where frozen (None where eq and not frozen, as the standard module makes it), frozen
instances refusing assignment (FrozenInstanceError), `slots=True` (a new class with `__slots__`), fields of base
records first, a method the class writes itself kept. Not supported (not used): order, kw_only, match_args,
InitVar, ClassVar.
"""

__all__ = ["dataclass", "field", "fields", "replace", "asdict", "Field", "FrozenInstanceError", "MISSING"]


class _Missing:
    __slots__ = ()

    def __repr__(self):
        return "MISSING"


MISSING = _Missing()                 # no default given
_FACTORY = _Missing()                # __init__'s default of a field made by its factory


class FrozenInstanceError(AttributeError):
    """An assignment to (or deletion of) a field of a frozen record."""


class Field:
    """One field of a record: its name, default or default factory, and whether __init__, __repr__ and
    __eq__/__hash__ take it."""
    __slots__ = ("name", "default", "default_factory", "init", "repr", "compare")

    def __init__(self, default=MISSING, default_factory=MISSING, init=True, repr=True, compare=True):
        if default is not MISSING and default_factory is not MISSING:
            raise ValueError("a field cannot have both a default and a default factory")
        self.name = None
        self.default, self.default_factory = default, default_factory
        self.init, self.repr, self.compare = init, repr, compare

    def __repr__(self):
        return "Field(name=%r, default=%r, default_factory=%r, init=%r, repr=%r, compare=%r)" % (
            self.name, self.default, self.default_factory, self.init, self.repr, self.compare)


def field(*, default=MISSING, default_factory=MISSING, init=True, repr=True, compare=True):
    """A field with more than a default (dataclasses.field's arguments of the same names)."""
    return Field(default, default_factory, init, repr, compare)


def fields(class_or_instance):
    """The Fields of a record class or instance, in order (base records' first)."""
    try:
        return class_or_instance.__record_fields__
    except AttributeError:
        raise TypeError("%r is not a record (mtlxgen.base.records)" % (class_or_instance,)) from None


def replace(obj, /, **changes):
    """A new record like `obj` with `changes` (dataclasses.replace): every init field not changed taken from
    `obj`, init=False fields made afresh by __init__ (changing one is an error)."""
    for f in fields(obj):
        if not f.init:
            if f.name in changes:
                raise ValueError("field %r is init=False: replace() cannot set it" % f.name)
        elif f.name not in changes:
            changes[f.name] = getattr(obj, f.name)
    return obj.__class__(**changes)


def asdict(obj):
    """A record as a dict of its fields, records, lists, tuples and dicts inside it converted too (dataclasses.asdict;
    other values shared, not copied)."""
    if hasattr(type(obj), "__record_fields__"):
        return {f.name: asdict(getattr(obj, f.name)) for f in fields(obj)}
    if isinstance(obj, (list, tuple)) and not hasattr(obj, "_fields"):
        return type(obj)(asdict(v) for v in obj)
    if isinstance(obj, dict):
        return type(obj)((asdict(k), asdict(v)) for k, v in obj.items())
    return obj


def dataclass(cls=None, /, *, frozen=False, slots=False, eq=True, repr=True):
    """The class `cls` made a record (used as @dataclass or @dataclass(...), as the standard decorator)."""
    def wrap(c):
        return _process(c, frozen, slots, eq, repr)
    return wrap if cls is None else wrap(cls)


def _collect(cls):
    """[Field] of `cls`: those of its base records, then its own annotations in order (a field redeclared
    replaces the base's in place)."""
    found = {}
    for base in reversed(cls.__mro__[1:]):
        for f in base.__dict__.get("__record_fields__", ()):
            found[f.name] = f
    for name in cls.__dict__.get("__annotations__", {}):
        value = cls.__dict__.get(name, MISSING)
        f = value if isinstance(value, Field) else Field(default=value)
        if isinstance(f.default, (list, dict, set)):
            raise ValueError("mutable default %s for field %s is not allowed: use default_factory"
                             % (type(f.default).__name__, name))
        f.name = name
        found[name] = f
    return list(found.values())


def _process(cls, frozen, slots, eq, repr_):
    flds = _collect(cls)
    _check_order(flds)
    owner = [cls]                   # the class the methods are for (the slotted class, where one is made)
    _put(cls, "__init__", _lazy(owner, "__init__", lambda c: _init_source(flds, frozen, hasattr(c, "__post_init__")),
                                flds))
    if repr_:
        _put(cls, "__repr__", _repr_of(tuple(f.name for f in flds if f.repr)))
    if eq:
        compared = tuple(f.name for f in flds if f.compare)
        _put(cls, "__eq__", _lazy(owner, "__eq__", lambda c: _eq_source(compared), flds))
        if "__hash__" not in cls.__dict__ or cls.__dict__["__hash__"] is None:
            cls.__hash__ = _lazy(owner, "__hash__", lambda c: _hash_source(compared), flds) if frozen else None
    if frozen:
        _put(cls, "__setattr__", _frozen_setattr)
        _put(cls, "__delattr__", _frozen_delattr)
    for f in flds:                                    # class attributes: the defaults, as the standard module
        if f.name in cls.__dict__ and isinstance(cls.__dict__[f.name], Field):
            if f.default is MISSING:
                delattr(cls, f.name)
            else:
                setattr(cls, f.name, f.default)
    cls.__record_fields__ = tuple(flds)
    if slots:
        cls = owner[0] = _with_slots(cls, flds)
    return cls


def _put(cls, name, value):
    if name not in cls.__dict__:                      # a method the class writes itself is kept
        setattr(cls, name, value)


# A record's __init__, __eq__ and __hash__ are compiled when first called, each by itself: a command uses a few
# of the methods of the records it imports, and compiling them all at import was most of the decorator's cost.
def _lazy(owner, name, source, flds):
    """A method `name` that compiles the real one (source(class): its text), puts it on its class in its place
    and runs it. The class is owner[0], the record's own (a record derived from it gets its own methods)."""
    def first_call(self, *args, **kwargs):
        cls = owner[0]
        method = _compile(name, source(cls), flds)
        if cls.__dict__.get(name) is first_call:
            setattr(cls, name, method)
        return method(self, *args, **kwargs)
    first_call.__name__ = first_call.__qualname__ = name
    return first_call


def _compile(name, text, flds):
    ns = {"MISSING": MISSING, "_FACTORY": _FACTORY, "_set": object.__setattr__}
    for f in flds:
        if f.default_factory is not MISSING:
            ns["_f_" + f.name] = f.default_factory
        elif f.default is not MISSING:
            ns["_d_" + f.name] = f.default
    exec(text, ns)
    return ns[name]


def _init_source(flds, frozen, post_init):
    params, body = [], []
    assign = "  _set(self, %r, %s)" if frozen else "  self.%s = %s"     # (a frozen record's own __setattr__ refuses)
    for f in flds:
        if f.init:
            if f.default_factory is not MISSING:
                params.append("%s=_FACTORY" % f.name)
                expr = "_f_%s() if %s is _FACTORY else %s" % (f.name, f.name, f.name)
            elif f.default is not MISSING:
                params.append("%s=_d_%s" % (f.name, f.name))
                expr = f.name
            else:
                params.append(f.name)
                expr = f.name
        elif f.default_factory is not MISSING:
            expr = "_f_%s()" % f.name
        elif f.default is not MISSING:
            expr = "_d_%s" % f.name
        else:
            continue                                  # init=False without a default: set later by the class
        body.append(assign % (f.name, expr))
    if post_init:
        body.append("  self.__post_init__()")
    return "\n".join(["def __init__(self%s):" % "".join(", " + p for p in params)] + (body or ["  pass"]))


def _check_order(flds):
    """The error the standard module gives where a field without a default follows one with a default."""
    seen_default = False
    for f in flds:
        if not f.init:
            continue
        if f.default is not MISSING or f.default_factory is not MISSING:
            seen_default = True
        elif seen_default:
            raise TypeError("non-default argument %r follows default argument" % f.name)


def _eq_source(names):
    mine = "(%s)" % "".join("self.%s, " % n for n in names)
    return "\n".join(["def __eq__(self, other):",
                      "  if other.__class__ is self.__class__:",
                      "    return %s == %s" % (mine, mine.replace("self.", "other.")),
                      "  return NotImplemented"])


def _hash_source(names):
    return "def __hash__(self):\n  return hash((%s))" % "".join("self.%s, " % n for n in names)


def _repr_of(names):
    def __repr__(self):
        return "%s(%s)" % (self.__class__.__qualname__, ", ".join("%s=%r" % (n, getattr(self, n)) for n in names))
    return __repr__


def _frozen_setattr(self, name, value):
    raise FrozenInstanceError("cannot assign to field %r" % name)


def _frozen_delattr(self, name):
    raise FrozenInstanceError("cannot delete field %r" % name)


def _with_slots(cls, flds):
    """`cls` made again with __slots__ for its own fields (no instance __dict__), as dataclass(slots=True)."""
    inherited = set()
    for base in cls.__mro__[1:]:
        inherited.update(getattr(base, "__slots__", ()))
    names = tuple(f.name for f in flds if f.name not in inherited)
    body = dict(cls.__dict__)
    for name in names:
        body.pop(name, None)                          # a default as a class attribute would hide the slot
    body.pop("__dict__", None)
    body.pop("__weakref__", None)
    body["__slots__"] = names
    made = type(cls)(cls.__name__, cls.__bases__, body)
    made.__qualname__ = cls.__qualname__
    return made
