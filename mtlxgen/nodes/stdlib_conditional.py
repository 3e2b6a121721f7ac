"""stdlib conditional and logic nodes (MaterialX Specification 1.39, "Conditional Nodes").

switch is a nodegraph in the data library (a chain of ifgreater on `which`).
"""

# the comparison of value1 and value2 each conditional category makes (fold.py also selects by it)
COMPARISONS = {"ifgreater": lambda a, b: bool(a > b), "ifgreatereq": lambda a, b: bool(a >= b),
               "ifequal": lambda a, b: bool(a == b)}


# evaluators (nodevalue.py): the templates' values in Python, term for term

def _select(category):
    op = COMPARISONS[category]

    def fn(i, t, o):
        return i["in1"] if op(i["value1"], i["value2"]) else i["in2"]
    return fn


def _compare(category):
    op = COMPARISONS[category]
    return lambda i, t, o: op(i["value1"], i["value2"])


NODES = {
    "ifgreater": {"expr": "({{value1}} > {{value2}}) ? {{in1}} : {{in2}}", "evaluate": _select("ifgreater")},
    "ifgreatereq": {"expr": "({{value1}} >= {{value2}}) ? {{in1}} : {{in2}}", "evaluate": _select("ifgreatereq")},
    "ifequal": {"expr": "({{value1}} == {{value2}}) ? {{in1}} : {{in2}}", "evaluate": _select("ifequal")},
    "and": {"expr": "{{in1}} && {{in2}}", "evaluate": lambda i, t, o: bool(i["in1"]) and bool(i["in2"])},
    "or": {"expr": "{{in1}} || {{in2}}", "evaluate": lambda i, t, o: bool(i["in1"]) or bool(i["in2"])},
    "xor": {"expr": "{{in1}} != {{in2}}", "evaluate": lambda i, t, o: bool(i["in1"]) != bool(i["in2"])},
    "not": {"expr": "!{{in}}", "evaluate": lambda i, t, o: not bool(i["in"])},
}

# boolean-valued comparisons have no in1/in2: the comparison itself is the result
NODEDEFS = {nd: {"expr": expr, "evaluate": _compare(category)} for category, names, expr in [
    ("ifgreater", ("ND_ifgreater_boolean", "ND_ifgreater_booleanI"), "{{value1}} > {{value2}}"),
    ("ifgreatereq", ("ND_ifgreatereq_boolean", "ND_ifgreatereq_booleanI"), "{{value1}} >= {{value2}}"),
    ("ifequal", ("ND_ifequal_boolean", "ND_ifequal_booleanI", "ND_ifequal_booleanB"), "{{value1}} == {{value2}}"),
] for nd in names}
