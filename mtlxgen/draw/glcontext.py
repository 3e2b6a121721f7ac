"""A headless OpenGL 4 context, for drawing (draw/renderer.py) and for compiling generated shaders (glslcheck.py)."""
import os


def create_context():
    """A headless OpenGL 4 context: EGL first (Mesa's llvmpipe on CPU machines), then OSMesa, then X11 when
    a display exists. MTLXGEN_GL_BACKEND=egl|osmesa|x11 picks one."""
    import moderngl
    forced = os.environ.get("MTLXGEN_GL_BACKEND", "").strip().lower()
    backends = [forced] if forced else ["egl", "osmesa"] + (["x11"] if os.environ.get("DISPLAY") else [])
    errors = []
    for backend in backends:
        try:
            if backend == "osmesa":
                from mtlxgen.draw.osmesa import create_context as osmesa_context
                ctx = osmesa_context()
            else:
                ctx = moderngl.create_standalone_context(backend=backend if backend != "x11" else None, require=400)
            if ctx.version_code < 400:
                raise RuntimeError("OpenGL %d, 4.0 needed" % ctx.version_code)
            return ctx
        except Exception as e:  # try the next backend
            errors.append("%s: %s" % (backend, str(e).strip().splitlines()[-1] if str(e).strip() else type(e).__name__))
    raise RuntimeError("no headless OpenGL 4 context (%s); install Mesa's EGL (libegl1 libgl1-mesa-dri) or "
                       "OSMesa (libosmesa6)" % "; ".join(errors))
