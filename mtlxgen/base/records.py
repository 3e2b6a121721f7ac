"""Plain data classes: the part of the standard library's `dataclasses` that mtlxgen uses, at a fraction of its
start-up cost.

Every record of the pipeline (a document's Port and Node, the graph's Source and GNode, a Shader, the options) is
declared as a data class: annotated fields with defaults, `field(default_factory=...)`, `frozen`, `slots`,
`eq=False`, `__post_init__`, `fields()`, `replace()` and `asdict()`. The standard module costs every command 35-40 ms before it
does any work: importing it imports `inspect` (8-11 ms), and it compiles each generated method of each class by
itself (25 classes on the path to a written shader: 25-30 ms). That was a quarter of a cold `mtlxgen generate`
(docs/measuring.md). This module writes the same methods, all of one class in one compile, and imports nothing.

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
    ns = {"MISSING": MISSING, "_FACTORY": _FACTORY, "FrozenInstanceError": FrozenInstanceError,
          "_set": object.__setattr__}
    params, body, seen_default = [], [], False
    assign = "  _set(self, %r, %s)" if frozen else "  self.%s = %s"     # (a frozen record's own __setattr__ refuses)
    for f in flds:
        if f.default_factory is not MISSING:
            ns["_f_" + f.name] = f.default_factory
        elif f.default is not MISSING:
            ns["_d_" + f.name] = f.default
        if f.init:
            if f.default_factory is not MISSING:
                params.append("%s=_FACTORY" % f.name)
                expr = "_f_%s() if %s is _FACTORY else %s" % (f.name, f.name, f.name)
                seen_default = True
            elif f.default is not MISSING:
                params.append("%s=_d_%s" % (f.name, f.name))
                expr = f.name
                seen_default = True
            else:
                if seen_default:
                    raise TypeError("non-default argument %r follows default argument" % f.name)
                params.append(f.name)
                expr = f.name
        elif f.default_factory is not MISSING:
            expr = "_f_%s()" % f.name
        elif f.default is not MISSING:
            expr = "_d_%s" % f.name
        else:
            continue                                  # init=False without a default: set later by the class
        body.append(assign % (f.name, expr))
    if hasattr(cls, "__post_init__"):
        body.append("  self.__post_init__()")
    lines = ["def __init__(self%s):" % "".join(", " + p for p in params)] + (body or ["  pass"])
    shown = [f for f in flds if f.repr]
    lines += ["def __repr__(self):",
              "  return self.__class__.__qualname__ + '(' + %s + ')'" % (
                  " + ', ' + ".join("%r + repr(self.%s)" % (f.name + "=", f.name) for f in shown) or "''")]
    compared = "(%s)" % "".join("self.%s, " % f.name for f in flds if f.compare)
    other = compared.replace("self.", "other.")
    lines += ["def __eq__(self, other):",
              "  if other.__class__ is self.__class__:",
              "    return %s == %s" % (compared, other),
              "  return NotImplemented",
              "def __hash__(self):",
              "  return hash(%s)" % compared,
              "def __setattr__(self, name, value):",
              "  raise FrozenInstanceError('cannot assign to field %r' % name)",
              "def __delattr__(self, name):",
              "  raise FrozenInstanceError('cannot delete field %r' % name)"]
    exec("\n".join(lines), ns)                   # one compile for every method of the class

    def put(name):
        if name not in cls.__dict__:                  # a method the class writes itself is kept
            setattr(cls, name, ns[name])
    put("__init__")
    if repr_:
        put("__repr__")
    if eq:
        put("__eq__")
        if "__hash__" not in cls.__dict__ or cls.__dict__["__hash__"] is None:
            cls.__hash__ = ns["__hash__"] if frozen else None
    if frozen:
        put("__setattr__")
        put("__delattr__")
    for f in flds:                                    # class attributes: the defaults, as the standard module
        if f.name in cls.__dict__ and isinstance(cls.__dict__[f.name], Field):
            if f.default is MISSING:
                delattr(cls, f.name)
            else:
                setattr(cls, f.name, f.default)
    cls.__record_fields__ = tuple(flds)
    if slots:
        cls = _with_slots(cls, flds)
    return cls


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
