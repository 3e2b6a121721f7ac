"""Pictures: the headless renderer (renderer: moderngl on EGL or OSMesa, glcontext), the environment and
lights that light it, IES profiles, meshes (geometry), image comparison, and compiling a document's own GLSL
(glslcheck).
"""
