"""Reading: .mtlx documents (xmlreader: expat, xi:include, file and line; upgrade: older versions to 1.39;
document: typed dataclasses and what a document renders), USD stages as documents (usdstage), and the data libraries
(library, library_cache: nodedefs, nodegraph implementations, the compact cache). source.load_document reads either.
"""
