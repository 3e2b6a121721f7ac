"""The graph passes after build, in order (order.PASSES): reduce (the reduced interface's constants), fold
(computing them), closures (closureplan: when each closure is needed, its guards decided on the condition tree).
Each takes a Graph and returns a new one.
"""
