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
