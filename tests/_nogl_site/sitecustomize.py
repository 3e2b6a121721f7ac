"""Loaded by Python subprocesses of tests not marked `gl` (tests/nogl_guard.py puts this folder on PYTHONPATH):
guards GLSL compiler (and, for tests not marked browser, browser) runs at once and moderngl's context factories once moderngl is imported (importing it here
would slow every subprocess). Does nothing unless MTLXGEN_TEST_NOGL_REPORT is set."""
import os


def _install():
    import importlib.abc
    import importlib.util
    import sys
    tests = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    spec = importlib.util.spec_from_file_location("_mtlxgen_nogl_guard", os.path.join(tests, "nogl_guard.py"))
    guard = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(guard)
    kinds = os.environ.get(guard.ENV_KINDS, "gl").split(",")
    guard.guard_programs(guard.child_refuse, [], kinds)
    if "gl" not in kinds:
        return

    class AfterModernglImport(importlib.abc.MetaPathFinder):
        def find_spec(self, fullname, path=None, target=None):
            if fullname != "moderngl":
                return None
            sys.meta_path.remove(self)
            spec = importlib.util.find_spec(fullname)
            if spec is None or spec.loader is None:
                return spec
            execute = spec.loader.exec_module

            def exec_module(module):
                execute(module)
                guard.guard_contexts(module, guard.child_refuse, [])      # (kind "gl" by default)
            spec.loader.exec_module = exec_module
            return spec

    sys.meta_path.insert(0, AfterModernglImport())


if os.environ.get("MTLXGEN_TEST_NOGL_REPORT"):
    _install()
