"""Shaders holding a document's own GLSL are compiled before they are written.

mtlxgen's GLSL is its own and tested; a document's (`<implementation sourcecode=...>` or `file=`) is only
checked as text before it is pasted (sourcecode.py), which cannot see types: `true` for a float output, a
swizzle a float lacks. So a shader holding such code is compiled with a headless OpenGL context (one per
process, made on first need), and a compile error becomes a problem at the implementation whose lines the
error points at. Where no OpenGL context can be made the check is skipped: generation needs none otherwise.
"""
import os
import re

from mtlxgen.base.diagnostics import MtlxError

# The compile context lives on a thread of its own: an OpenGL context is current per thread, so the
# check never changes which context the caller's thread (a Renderer's, say) has current.
_WORKER = {}            # pid -> (one-thread executor, [context or None once tried])


def _worker():
    pid = os.getpid()       # a forked child gets a thread (and a context) of its own
    if pid not in _WORKER:
        import concurrent.futures      # here, not at the top: most shaders hold no document GLSL (logging, 5 ms)
        _WORKER.clear()
        _WORKER[pid] = (concurrent.futures.ThreadPoolExecutor(1, thread_name_prefix="mtlxgen-glslcheck"), [])
    return _WORKER[pid]


def _thread_context(tried):
    if not tried:
        try:
            from mtlxgen.draw.glcontext import create_context
            tried.append(create_context())
        except Exception:       # no Mesa / no moderngl: nothing to compile with
            tried.append(None)
    return tried[0]


def _compile(tried, vertex, fragment):
    """On the worker thread: None when the stages link (or nothing can compile them), else the driver's log."""
    ctx = _thread_context(tried)
    if ctx is None:
        return None
    try:
        ctx.program(vertex_shader=vertex, fragment_shader=fragment).release()
    except Exception as e:      # moderngl.Error carrying the driver's log
        return str(e) or type(e).__name__
    return None


def context():
    """Make the compile context now (False where OpenGL is missing). A caller that watches which files a run
    opens can call this first: creating a context opens the driver's files."""
    pool, tried = _worker()
    return pool.submit(_thread_context, tried).result() is not None


def check(shader):
    """The shader, once its document GLSL compiles; MtlxError at the implementation at fault otherwise."""
    if not shader.document_code:
        return shader
    pool, tried = _worker()
    from mtlxgen.base.targets import for_opengl
    vertex, fragment = for_opengl(shader.vertex), for_opengl(shader.fragment)
    log = pool.submit(_compile, tried, vertex, fragment).result()
    if log is not None:
        raise MtlxError(problems(shader, log))
    return shader


# Mesa: "fragment_shader\n===\n0:12(5): error: ..."; glslang-style drivers: "ERROR: 0:12: ..."
_MESA = re.compile(r"^\d+:(\d+)\(\d+\): error: (.*)$", re.M)
_OTHER = re.compile(r"^ERROR: \d+:(\d+): (.*)$", re.M)


def problems(shader, log):
    """(Loc, message) for the document implementations the first error of a driver's `log` points at: the
    one whose lines hold the erring line, else every one in the shader."""
    m = _MESA.search(log) or _OTHER.search(log)
    if m is None:
        message, line_text = (log.strip().splitlines() or ["link failed"])[-1].strip(), None
    else:
        message = m.group(2).strip()
        stage = shader.vertex if log.rfind("vertex_shader", 0, m.start()) > log.rfind("fragment_shader", 0, m.start()) \
            else shader.fragment
        lines = stage.splitlines()
        number = int(m.group(1))
        line_text = lines[number - 1].strip() if 0 < number <= len(lines) else None
    at_fault = [source for source, made in shader.document_code if line_text in made] or \
        [source for source, _ in shader.document_code]
    return [(loc, "implementation '%s': its GLSL does not compile: %s" % (name, message)) for name, loc in at_fault]
