"""Off-screen OpenGL through Mesa's OSMesa (libOSMesa), for machines where EGL gives no context.

moderngl accepts any loader that resolves GL function names (moderngl.init_context); this one creates
an OSMesa core-profile context with ctypes, makes it current on a 1x1 buffer (we draw into our own
framebuffer objects) and resolves functions with OSMesaGetProcAddress.
"""
import ctypes
import ctypes.util

# OSMesa constants (GL/osmesa.h)
OSMESA_RGBA = 0x1908
OSMESA_DEPTH_BITS = 0x30
OSMESA_STENCIL_BITS = 0x31
OSMESA_ACCUM_BITS = 0x32
OSMESA_PROFILE = 0x33
OSMESA_CORE_PROFILE = 0x34
OSMESA_CONTEXT_MAJOR_VERSION = 0x36
OSMESA_CONTEXT_MINOR_VERSION = 0x37
OSMESA_FORMAT = 0x22
GL_UNSIGNED_BYTE = 0x1401


def _library():
    name = ctypes.util.find_library("OSMesa")
    for cand in ([name] if name else []) + ["libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"]:
        try:
            return ctypes.CDLL(cand)
        except OSError:
            continue
    raise RuntimeError("libOSMesa not found (Debian: apt-get install libosmesa6)")


class OSMesaLoader:
    """A current OSMesa context and the function loader moderngl asks for."""

    def __init__(self, major=4, minor=5):
        lib = self.lib = _library()
        lib.OSMesaCreateContextAttribs.restype = ctypes.c_void_p
        lib.OSMesaCreateContextAttribs.argtypes = [ctypes.POINTER(ctypes.c_int), ctypes.c_void_p]
        lib.OSMesaMakeCurrent.restype = ctypes.c_ubyte
        lib.OSMesaMakeCurrent.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_int, ctypes.c_int, ctypes.c_int]
        lib.OSMesaGetProcAddress.restype = ctypes.c_void_p
        lib.OSMesaGetProcAddress.argtypes = [ctypes.c_char_p]
        lib.OSMesaDestroyContext.argtypes = [ctypes.c_void_p]
        attribs = (ctypes.c_int * 15)(OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_STENCIL_BITS, 8,
                                      OSMESA_ACCUM_BITS, 0, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                                      OSMESA_CONTEXT_MAJOR_VERSION, major, OSMESA_CONTEXT_MINOR_VERSION, minor, 0)
        self.ctx = lib.OSMesaCreateContextAttribs(attribs, None)
        if not self.ctx:
            raise RuntimeError("OSMesa could not create an OpenGL %d.%d core context" % (major, minor))
        self.buffer = (ctypes.c_ubyte * 4)()
        self.make_current()

    def make_current(self):
        if not self.lib.OSMesaMakeCurrent(self.ctx, ctypes.cast(self.buffer, ctypes.c_void_p), GL_UNSIGNED_BYTE, 1, 1):
            raise RuntimeError("OSMesaMakeCurrent failed")

    # the loader protocol of moderngl.init_context
    def load_opengl_function(self, name):
        return self.lib.OSMesaGetProcAddress(name.encode()) or 0

    def load(self, name):
        return self.load_opengl_function(name)

    def release(self):
        if self.ctx:
            self.lib.OSMesaDestroyContext(self.ctx)
            self.ctx = None

    def __enter__(self):
        self.make_current()
        return self

    def __exit__(self, *exc):
        pass


def create_context():
    """A moderngl Context on OSMesa (the loader is kept on ctx.extra so it lives as long as the context)."""
    import moderngl
    loader = OSMesaLoader()
    moderngl.init_context(loader)
    ctx = moderngl.get_context()
    moderngl._store.default_context = None        # later get_context() calls must not pick this one up
    ctx.extra = {"osmesa": loader}
    return ctx
