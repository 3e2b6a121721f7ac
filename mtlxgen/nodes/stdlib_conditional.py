"""stdlib conditional and logic nodes (MaterialX Specification 1.39, "Conditional Nodes").

switch is a nodegraph in the data library (a chain of ifgreater on `which`).
"""

NODES = {
    "ifgreater": "({{value1}} > {{value2}}) ? {{in1}} : {{in2}}",
    "ifgreatereq": "({{value1}} >= {{value2}}) ? {{in1}} : {{in2}}",
    "ifequal": "({{value1}} == {{value2}}) ? {{in1}} : {{in2}}",
    "and": "{{in1}} && {{in2}}",
    "or": "{{in1}} || {{in2}}",
    "xor": "{{in1}} != {{in2}}",
    "not": "!{{in}}",
}

# boolean-valued comparisons have no in1/in2: the comparison itself is the result
NODEDEFS = {nd: expr for names, expr in [
    (("ND_ifgreater_boolean", "ND_ifgreater_booleanI"), "{{value1}} > {{value2}}"),
    (("ND_ifgreatereq_boolean", "ND_ifgreatereq_booleanI"), "{{value1}} >= {{value2}}"),
    (("ND_ifequal_boolean", "ND_ifequal_booleanI", "ND_ifequal_booleanB"), "{{value1}} == {{value2}}"),
] for nd in names}
