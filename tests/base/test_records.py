"""mtlxgen.base.records against the standard library's dataclasses: the same classes declared with each behave
alike in everything mtlxgen uses (construction, defaults and factories, repr, equality, hashing, frozen instances,
slots, __post_init__, init=False fields, base records, fields(), replace())."""
import dataclasses
import pickle

import pytest

from mtlxgen.base import records


def _declare(dc, field, **options):
    @dc(**options)
    class Base:
        name: str
        kind: str = "input"

    @dc(**options)
    class Rec(Base):
        """A record."""
        value: object = None
        items: list = field(default_factory=list)
        hidden: dict = field(default_factory=dict, repr=False, compare=False)

    return Rec


@pytest.mark.parametrize("options", [{}, {"frozen": True}, {"slots": True}, {"eq": False}, {"frozen": True, "eq": False}],
                         ids=["plain", "frozen", "slots", "no-eq", "frozen-no-eq"])
def test_records_behave_as_dataclasses(options):
    std = _declare(dataclasses.dataclass, dataclasses.field, **options)
    own = _declare(records.dataclass, records.field, **options)
    for args, kwargs in (((), {"name": "a"}), (("a", "output", 1.5, [1]), {}), ((), {"name": "b", "hidden": {1: 2}})):
        s, o = std(*args, **kwargs), own(*args, **kwargs)
        assert repr(s) == repr(o)
        assert [getattr(s, f.name) for f in dataclasses.fields(s)] == [getattr(o, f.name) for f in records.fields(o)]
        assert [f.name for f in dataclasses.fields(std)] == [f.name for f in records.fields(own)]
        for change in ({"value": 3}, {"name": "c", "items": [2]}):
            assert repr(dataclasses.replace(s, **change)) == repr(records.replace(o, **change))
        twin_s, twin_o = std(*args, **kwargs), own(*args, **kwargs)
        assert (s == twin_s) == (o == twin_o)
        assert (s == dataclasses.replace(s, hidden={9: 9})) == (o == records.replace(o, hidden={9: 9}))
        assert (o == object()) is False
        assert (type(s).__hash__ is None) == (type(o).__hash__ is None)
        for a, b in ((s, twin_s), (o, twin_o)):         # (a list field: unhashable either way)
            try:
                hashes = hash(a) == hash(b)
            except TypeError as e:
                hashes = str(e)
            if a is s:
                std_hashes = hashes
        assert hashes == std_hashes
        assert hasattr(s, "__dict__") == hasattr(o, "__dict__")
    assert std(name="x").items is not std(name="x").items
    assert own(name="x").items is not own(name="x").items
    if not options.get("slots"):
        assert getattr(std, "kind", None) == getattr(own, "kind", None)   # defaults as class attributes
    if options.get("frozen"):
        o = own("a")
        with pytest.raises(records.FrozenInstanceError):
            o.name = "b"
        with pytest.raises(AttributeError):
            del o.name
    if options.get("slots"):
        with pytest.raises(AttributeError):
            own("a").other = 1


def test_post_init_init_false_and_errors():
    seen = []

    @records.dataclass
    class Checked:
        kind: str
        memo: dict = records.field(default_factory=dict, init=False, repr=False, compare=False)

        def __post_init__(self):
            seen.append(self.kind)
            if self.kind not in ("a", "b"):
                raise ValueError("kind")

    c = Checked("a")
    assert seen == ["a"] and c.memo == {} and repr(c) == "test_post_init_init_false_and_errors.<locals>.Checked(kind='a')"
    with pytest.raises(ValueError):
        Checked("z")
    with pytest.raises(ValueError):
        records.replace(c, memo={})
    assert records.replace(c, kind="b").memo == {}
    with pytest.raises(ValueError, match="mutable default"):
        @records.dataclass
        class Bad:
            items: list = []
    with pytest.raises(TypeError, match="follows default"):
        @records.dataclass
        class Order:
            a: int = 0
            b: int
    with pytest.raises(TypeError, match="not a record"):
        records.fields(object())


def test_methods_are_compiled_once_for_their_own_class():
    @records.dataclass
    class Base:
        a: int = 1

    @records.dataclass
    class Derived(Base):
        b: int = 2

    class Plain(Base):              # not a record itself: the base's methods
        pass

    stub = Base.__dict__["__init__"]
    assert Plain(5).a == 5 and Base.__dict__["__init__"] is not stub      # compiled on the first call, kept
    assert Derived(3, 4) == Derived(3, 4) and Derived(3, 4) != Derived(3, 5) and Base(3) != Derived(3)
    assert repr(Derived()) == "test_methods_are_compiled_once_for_their_own_class.<locals>.Derived(a=1, b=2)"
    assert "__init__" in Derived.__dict__ and Derived.__dict__["__init__"] is not Base.__dict__["__init__"]


def test_a_method_the_class_writes_is_kept_and_records_pickle():
    @records.dataclass
    class Shown:
        a: int = 1

        def __repr__(self):
            return "shown"

    assert repr(Shown()) == "shown"
    p = Point(1.0, 2.0)
    assert pickle.loads(pickle.dumps(p)) == p
    s = Slotted(1, [2])
    assert pickle.loads(pickle.dumps(s)) == s


@records.dataclass(frozen=True)
class Point:
    x: float
    y: float = 0.0


@records.dataclass(slots=True)
class Slotted:
    a: int
    b: list = records.field(default_factory=list)


def test_the_package_does_not_import_dataclasses_on_its_way_to_a_shader(tmp_path):
    """What the records are for: `mtlxgen generate` neither imports dataclasses nor (through it) inspect."""
    import subprocess
    import sys
    code = ("import sys, mtlxgen.apps.cli, mtlxgen.api, mtlxgen.pipeline; "
            "print(sorted(m for m in ('dataclasses', 'inspect', 'typing', 'tempfile', 'shutil') if m in sys.modules))")
    # -I: the interpreter as a user starts it (no PYTHONPATH: the test guard's sitecustomize imports more)
    out = subprocess.run([sys.executable, "-I", "-c", code], capture_output=True, text=True, check=True,
                         cwd=str(tmp_path)).stdout
    assert out.strip() == "[]", out
