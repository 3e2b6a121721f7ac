"""The typed graph, the IR every later stage reads (graphtypes: Source, GNode, Uniform and its Origin, Graph), and
how a document's element becomes one (build: nodedefs resolved, connections type-checked, defaults filled in,
nodegraph implementations expanded or called as functions: functions); graphwalk's walks; transparency: MaterialX's
isTransparentSurface on the document.
"""
