"""The vocabulary every stage shares: problems and warnings with FILE:LINE (diagnostics), which files may be read
and how far (files, resolve), MaterialX's types and values (mxtypes), colour spaces, GLSL identifiers, the shader's
application interface table (interface), geometric streams, targets, image files. Imports nothing of mtlxgen's.
"""
