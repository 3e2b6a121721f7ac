"""GLSL from a graph: the emitter (vertex and fragment stages, the manifest, nodegraph implementations as
functions), inline templates (template), main's lines (stagewriter), the glsl_lib code a stage reaches (glsldeps).
"""
