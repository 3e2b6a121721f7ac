"""Command line: mtlxgen generate | render | info.

Errors in input print one `FILE:LINE: problem` line each on stderr and exit with status 1;
usage errors exit with 2. No tracebacks for bad input.
"""
import argparse
import os
import sys

from .diagnostics import MtlxError


def _report(e):
    for line in e.lines():
        print(line, file=sys.stderr)
    return 1


def cmd_generate(args):
    from . import pipeline
    shaders, error = pipeline.generate(args.file, [args.element] if args.element else None, args.library,
                                       partial=True)
    for s in shaders:
        paths = s.write(args.output)
        if args.verbose:
            print("\n".join(paths))
    if error is not None:
        raise error
    return 0


def cmd_render(args):
    from . import pipeline, render
    shaders = pipeline.generate(args.file, [args.element] if args.element else None, args.library)
    env = render.load_environment(args.env) if args.env else None
    with render.Renderer(size=args.size, environment=env) as r:
        for s in shaders:
            img = r.render(s)
            os.makedirs(args.output, exist_ok=True)
            base = os.path.join(args.output, s.stem)
            render.write_image(base + ".png", img)
            render.write_image(base + ".exr", img)
            print(base + ".png")
    return 0


def cmd_info(args):
    from . import graph, library, pipeline
    lib = library.load_library(args.library)
    doc = pipeline.load_document(args.file, args.library)
    print("%s (MaterialX %s)" % (args.file, doc.version))
    names = graph.renderable_elements(doc)
    status = 0
    for name in names:
        try:
            g = graph.build_graph(doc, lib, name)
            print("  %s [%s] %d nodes, %d uniforms" % (name, g.kind, len(g.nodes), len(g.uniforms)))
            for n in g.nodes:
                print("    %-28s %s" % (n.id, n.nodedef.name))
        except MtlxError as e:
            status = 1
            print("  %s: unresolved" % name)
            for line in e.lines():
                print("    " + line)
    return status


def build_parser():
    ap = argparse.ArgumentParser(prog="mtlxgen", description="MaterialX documents to GLSL shaders")
    sub = ap.add_subparsers(dest="command", required=True)

    def common(p):
        p.add_argument("file", help="a .mtlx document")
        p.add_argument("--library", action="append", default=[], metavar="DIR",
                       help="extra directory of .mtlx definitions (repeatable)")

    p = sub.add_parser("generate", help="write NAME.vert, NAME.frag, NAME.json per renderable element")
    common(p)
    p.add_argument("-o", "--output", required=True, metavar="DIR")
    p.add_argument("--element", metavar="NAME", help="only this element (name path)")
    p.add_argument("-v", "--verbose", action="store_true", help="print the paths written")
    p.set_defaults(func=cmd_generate)

    p = sub.add_parser("render", help="render each element on a sphere to NAME.png (sRGB) and NAME.exr (linear)")
    common(p)
    p.add_argument("-o", "--output", required=True, metavar="DIR")
    p.add_argument("--element", metavar="NAME")
    p.add_argument("--size", type=int, default=256)
    p.add_argument("--env", metavar="FILE", help="lat-long HDR/EXR environment (default: built-in sky)")
    p.set_defaults(func=cmd_render)

    p = sub.add_parser("info", help="list elements, their nodes and unresolved problems")
    common(p)
    p.set_defaults(func=cmd_info)
    return ap


def main(argv=None):
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except MtlxError as e:
        return _report(e)
    except KeyboardInterrupt:
        return 130
    except RecursionError:
        print("%s: error: the document nests too deeply to process" % getattr(args, "file", "mtlxgen"), file=sys.stderr)
        return 1
    except Exception as e:     # a bug of ours: one line, the traceback only on request
        if os.environ.get("MTLXGEN_DEBUG"):
            raise
        print("%s: internal error: %s: %s (set MTLXGEN_DEBUG=1 for details)"
              % (getattr(args, "file", "mtlxgen"), type(e).__name__, e), file=sys.stderr)
        return 3


if __name__ == "__main__":
    sys.exit(main())
