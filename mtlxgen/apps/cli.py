"""Command line: mtlxgen generate | render | info | view | web | three | golden check/update | report | batch.

Errors in input print one `FILE:LINE: problem` line each on stderr and exit with status 1; so do
usage errors and bad option values (`mtlxgen CMD: error: argument OPT: problem`), checked before any
work starts. No tracebacks for bad input; exit 3 is kept for our own bugs.
"""
import argparse
import math
import os
import sys

from mtlxgen.base.diagnostics import Loc, MtlxError, Warnings
from mtlxgen.base.interface import LIGHTS_LIMIT
from mtlxgen.base.targets import NAMES as TARGET_NAMES


def _report(e):
    for line in e.lines():
        print(line, file=sys.stderr)
    return 1


def _print_warnings(lines):
    """`FILE:LINE: warning: ...` lines on stderr, each once (slips MaterialX reads on; --strict makes them errors)."""
    for line in dict.fromkeys(lines):
        print(line, file=sys.stderr)


# emit.ENVIRONMENT_METHODS (tests/read/test_library_index.py holds them equal): options.py's, so that `mtlxgen --help`
# does not import the emitter
from mtlxgen.options import ENVIRONMENT_METHODS, GenerateOptions  # noqa: E402


# ---------------------------------------------------------------- option values
# argparse calls these on each value; ArgumentTypeError becomes "argument OPT: message" (one line).

MAX_SIZE = 8192        # an 8192² float RGBA framebuffer is already 1 GiB
MAX_WORKERS = 256      # each worker is a process with its own GL context


def _terminal_columns():
    """shutil.get_terminal_size's columns ($COLUMNS, else the terminal's, else 80), without importing shutil (with
    bz2 and lzma: 4 ms of every command's start, argparse's formatter imports it for the width alone)."""
    try:
        columns = int(os.environ.get("COLUMNS", "0"))
    except ValueError:
        columns = 0
    if columns <= 0:
        try:
            columns = os.get_terminal_size(sys.__stdout__.fileno()).columns
        except (AttributeError, ValueError, OSError):
            columns = 0
    return columns or 80


class _Formatter(argparse.HelpFormatter):
    def __init__(self, prog, indent_increment=2, max_help_position=24, width=None):
        super().__init__(prog, indent_increment, max_help_position,
                         _terminal_columns() - 2 if width is None else width)


class _Parser(argparse.ArgumentParser):
    """Usage errors are one line and exit 1, like every other bad input (argparse prints usage, exits 2)."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", _Formatter)
        super().__init__(*args, **kwargs)

    def error(self, message):
        self.exit(1, "%s: error: %s (see %s --help)\n" % (self.prog, " ".join(message.split()), self.prog))


def _bad(text, problem):
    return argparse.ArgumentTypeError("%s: %s" % (text, problem) if text else "empty path: %s" % problem)


def _int_in(lo, hi):
    def whole_number(text):
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError("%r is not a whole number" % text) from None
        if not lo <= v <= hi:
            raise argparse.ArgumentTypeError("%d is out of range: must be %d to %d" % (v, lo, hi))
        return v
    return whole_number


def _float_in(lo, hi):
    def number(text):
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError("%r is not a number" % text) from None
        if not (math.isfinite(v) and lo <= v <= hi):
            raise argparse.ArgumentTypeError("%s is out of range: must be %g to %g" % (text, lo, hi))
        return v
    return number


def _readable_file(text):
    if not os.path.exists(text):
        raise _bad(text, "no such file")
    if os.path.isdir(text):
        raise _bad(text, "is a directory, not a file")
    if not os.path.isfile(text):                     # devices and FIFOs: reading them may never end
        raise _bad(text, "not a regular file")
    if not os.access(text, os.R_OK):
        raise _bad(text, "not readable")
    return text


def _existing_dir(text):
    if not os.path.exists(text):
        raise _bad(text, "no such directory")
    if not os.path.isdir(text):
        raise _bad(text, "not a directory")
    if not os.access(text, os.R_OK | os.X_OK):
        raise _bad(text, "directory not readable")
    return text


def _creatable(path):
    """None when a directory could be made at PATH (missing parts and all), else why not."""
    if os.path.lexists(path) and not os.path.exists(path):
        return "a dangling symbolic link"
    parent = os.path.abspath(path)
    while not os.path.exists(parent):
        parent = os.path.dirname(parent)
    if not os.path.isdir(parent):
        return "cannot create it: %s is not a directory" % parent
    if not os.access(parent, os.W_OK | os.X_OK):
        return "cannot write in %s" % parent
    return None


def _output_dir(text):
    if os.path.exists(text) and not os.path.isdir(text):
        raise _bad(text, "exists and is not a directory")
    why = _creatable(text) if text else "not a directory name"
    if why:
        raise _bad(text, why)
    return text


def _output_file(text):
    if not text:
        raise _bad(text, "not a file name")
    if text.endswith(os.sep) or os.path.isdir(text):
        raise _bad(text, "is a directory, not a file name")
    if os.path.lexists(text) and not os.path.isfile(text):
        raise _bad(text, "exists and is not a regular file")
    why = _creatable(os.path.dirname(os.path.abspath(text)))
    if why:
        raise _bad(text, why)
    return text


def _name(text):
    if not text.strip():
        raise argparse.ArgumentTypeError("an element name must not be empty")
    return text


def _variant(text):
    set_name, eq, variant = text.partition("=")
    if not eq or not set_name.strip() or not variant.strip():
        raise argparse.ArgumentTypeError("%r is not SET=NAME (a variant set and the variant to select)" % text)
    return set_name.strip(), variant.strip()


def _usd_options(args):
    """usdstage.StageOptions from --variant / --render-context; an error where they are given for a .mtlx."""
    return GenerateOptions(variants=tuple(getattr(args, "variant", None) or ()),
                           render_context=getattr(args, "render_context", None)).stage_options(args.file)


def _check_document(path):
    """The input document: FILE:0 style like every other problem with a file."""
    problem = ("no such file" if not os.path.exists(path) else
               "is a directory, not a .mtlx document" if os.path.isdir(path) else
               "not a regular file" if not os.path.isfile(path) else
               "not readable" if not os.access(path, os.R_OK) else None)
    if problem:
        raise MtlxError((Loc(path or "<empty path>", 0), problem))


def _generate(args, rig=(), unreadable_textures="error"):
    """(shaders that worked, MtlxError or None) for generate, render, web and three; warnings printed either way.
    rig, unreadable_textures: _options'. The public API's generation (api.generate_partial)."""
    from mtlxgen import api
    warnings = Warnings()
    try:
        return api.generate_partial(args.file, [args.element] if args.element else None,
                                    _options(args, rig, unreadable_textures), warnings=warnings)
    finally:
        _print_warnings(warnings.lines())


def _options(args, rig=(), unreadable_textures="error"):
    """The options.GenerateOptions of a command's options: what each command has of --library, --strict,
    --usd-seed-rules, --environment, --variant, --render-context, --interface, --keep, --keep-file, --max-lights and
    --target (argparse checked each value; a keep file's problems: FILE:LINE). rig: the lights render binds (its
    shaders take as many, where --max-lights does not say; web and three have no --max-lights: their pages bind no
    lights). unreadable_textures: "error" for the commands that draw, "warning" for generate."""
    lights = getattr(args, "max_lights", None)
    if lights is None:
        lights = len(rig)
    kind, keep = _interface(args) if hasattr(args, "keep") else ("complete", ())
    return GenerateOptions(target=getattr(args, "target", "glsl"), interface=kind, keep=keep,
                           environment=getattr(args, "environment", "fis"), max_lights=lights,
                           strict=getattr(args, "strict", False),
                           usd_seed_rules=getattr(args, "usd_seed_rules", None),
                           library_dirs=tuple(getattr(args, "library", None) or ()),
                           variants=tuple(getattr(args, "variant", None) or ()),
                           render_context=getattr(args, "render_context", None),
                           unreadable_textures=unreadable_textures)


def _interface(args):
    """(interface kind, [(name, Loc or None)] kept) of --interface, --keep and --keep-file (a keep file's problems:
    FILE:LINE)."""
    from mtlxgen.passes import reduce
    if (args.keep or args.keep_file) and args.interface == "complete":
        raise MtlxError((Loc(args.keep_file or getattr(args, "file", None) or "mtlxgen", 0),
                         "--keep and --keep-file name inputs kept editable in the reduced interface (every input "
                         "is a uniform in the complete one): use them with --interface reduced"))
    kind = args.interface or ("reduced" if args.keep or args.keep_file else "complete")
    keep = [(n, None) for n in args.keep] + (reduce.read_keep_file(args.keep_file) if args.keep_file else [])
    return kind, keep


def cmd_generate(args):
    shaders, error = _generate(args, unreadable_textures="warning")
    for s in shaders:
        paths = s.write(args.output, absolute_paths=args.absolute_paths)
        if args.verbose:
            print("\n".join(paths))
        elif not args.quiet:        # one line an element: DIR/STEM.{vert,frag,json}
            print("wrote %s.{vert,frag,json}" % os.path.join(args.output, s.stem))
    if error is not None:
        raise error
    return 0


def cmd_render(args):
    from mtlxgen import pipeline
    from mtlxgen.draw import renderer as render
    if args.geometry == "stage" and _usd_options(args) is None:
        raise MtlxError((Loc(args.file, 0), "--geometry stage draws a USD stage's meshes; this is a MaterialX document"))
    from mtlxgen.draw.lights import load_light_rig
    lights = load_light_rig(args.lights) if args.lights else ()
    if args.max_lights is not None and args.max_lights < len(lights):
        raise MtlxError((Loc(args.lights, 0), "the light rig holds %d lights; --max-lights %d cannot draw them"
                         % (len(lights), args.max_lights)))
    # elements with problems are reported, the others drawn (as generate writes them)
    shaders, error = _generate(args, lights)
    env = render.load_environment(args.env) if args.env else None
    problems = list(error.problems) if error is not None else []
    with render.Renderer(size=args.size, environment=env, lights=lights) as r:
        for s in shaders:
            try:
                img = r.render(s)
            except MtlxError as e:      # a file the renderer refuses: this element is not drawn, the others are
                problems += [p for p in pipeline.at_inputs(s, e).problems if p not in problems]
                continue
            os.makedirs(args.output, exist_ok=True)
            base = os.path.join(args.output, s.stem)
            render.write_image(base + ".png", img)
            render.write_image(base + ".exr", img)
            print(base + ".png")
        if args.geometry == "stage":
            problems += _render_stage(args, r, shaders)
    if problems:
        raise MtlxError(problems)
    return 0


def _render_stage(args, r, shaders):
    """--geometry stage: the stage's meshes with their materials' shaders, to DIR/STEM__stage.png and .exr."""
    from mtlxgen.draw import renderer as render
    from mtlxgen.apps import stagerender
    view = stagerender.read_view(args.file, args.library, _usd_options(args))
    img = stagerender.render_stage(r, view, {s.element: s for s in shaders},
                                   stagerender.fallback_shader(args.environment))
    os.makedirs(args.output, exist_ok=True)
    base = os.path.join(args.output, os.path.splitext(os.path.basename(args.file))[0] + "__stage")
    render.write_image(base + ".png", img)
    render.write_image(base + ".exr", img)
    print(base + ".png")
    return view.problems


def _geometry(text):
    from mtlxgen.draw.geometry import BUILTIN
    return text if text in BUILTIN else _readable_file(text)


def _samples(text):
    from mtlxgen.apps.view import SAMPLE_STEPS
    v = _int_in(1, 65536)(text)
    if v & (v - 1):
        raise argparse.ArgumentTypeError("%d is not a power of two (e.g. %s)" % (v, ", ".join(map(str, SAMPLE_STEPS))))
    return v


def cmd_view(args):
    from mtlxgen.apps import view
    args.generate_options = _options(args)
    args.usd_options = args.generate_options.stage_options(args.file)
    if (args.screenshot or args.capture_window) and args.headless_frames is None:
        raise MtlxError((Loc(args.file, 0), "--screenshot and --capture-window go with --headless-frames N "
                                            "(in the window: key C)"))
    return view.run(args)


def _web_shaders(args):
    """web, three: each element's GLSL ES 3.00 shaders (elements with problems reported, the others written),
    and the environment (--env, bounded for a page; None: the built-in sky)."""
    from mtlxgen.apps import web
    env = web.read_environment(args.env) if args.env else None
    shaders, error = _generate(args)
    return shaders, env, list(error.problems) if error is not None else []


def cmd_web(args):
    from mtlxgen import pipeline
    from mtlxgen.apps import web
    shaders, env, problems = _web_shaders(args)
    environment = web.environment_payload(env) if shaders else None
    for s in shaders:
        try:
            print(web.write_page(s, args.output, environment, args.size, args.samples))
        except MtlxError as e:      # a texture the page cannot embed: this element is not written, the others are
            problems += [p for p in pipeline.at_inputs(s, e).problems if p not in problems]
    if problems:
        raise MtlxError(problems)
    return 0


def cmd_three(args):
    from mtlxgen import pipeline
    from mtlxgen.apps import three
    shaders, env, problems = _web_shaders(args)
    if shaders:
        os.makedirs(args.output, exist_ok=True)
        three.write_runtime(args.output)
        three.write_environment(args.output, env)
    textures = three.TextureFiles(args.output)
    for s in shaders:
        try:
            print(three.write_element(s, args.output, textures, args.size, args.samples)[0])
        except MtlxError as e:
            problems += [p for p in pipeline.at_inputs(s, e).problems if p not in problems]
    if problems:
        raise MtlxError(problems)
    return 0


def cmd_info(args):
    from mtlxgen import pipeline
    options = _options(args)
    if options.stage_options(args.file) is not None:
        from mtlxgen.apps.usdinfo import print_info
        return print_info(args.file, options)
    warnings = Warnings()
    try:
        return _info(pipeline.Session(args.file, options, warnings=warnings))
    finally:
        _print_warnings(warnings.lines())


def _info(session):
    print("%s (MaterialX %s)" % (session.path, session.doc.version))
    status = 0
    for name in session.elements:
        try:
            g = session.graph(name)
            print("  %s [%s] %d nodes, %d uniforms" % (name, g.kind, len(g.nodes), len(g.uniforms)))
            for n in g.nodes:
                print("    %-28s %s" % (n.id, n.nodedef.name))
        except MtlxError as e:
            status = 1
            print("  %s: unresolved" % name)
            for line in e.lines():
                print("    " + line)
    return status


def _show(path):
    """A path as the user would type it: relative below the current directory, else absolute."""
    rel = os.path.relpath(path)
    return os.path.abspath(path) if rel.startswith("..") else rel


def _print_check(run, verbose=False):
    rel = _show
    for r in run.results:
        if r["status"] == "pass" and not verbose:
            continue
        m = r["metrics"]
        flip = m.get("flip")
        print("%-7s %s (%s:%s)%s" % (r["status"].upper(), r["name"], r["source"], r["element"],
                                     "" if flip is None else "  FLIP %.5f" % flip))
        for line in r["message"]:
            print("        " + line)
        if r["status"] == "fail" and r["files"]:        # (none where they could not be written: said above)
            print("        " + "  ".join("%s: %s" % (k, rel(os.path.join(run.out_dir, r["files"][k])))
                                        for k in ("new", "golden", "diff") if k in r["files"]))
    for note in run.notes:
        print("note: " + note, file=sys.stderr)


def cmd_golden_check(args):
    from mtlxgen.apps import golden, report
    tol = golden.Tolerance(threshold=args.threshold, max_fraction=args.max_fraction, flip=args.flip_limit)
    warnings = []
    run = golden.check(args.paths, args.goldens or golden.DEFAULT_DIR, args.output, tol, workers=args.workers,
                       progress=False if args.no_progress else None, flip=not args.no_flip, warnings=warnings,
                       options=_options(args), scheduler=args.scheduler, shard=args.shard)
    _print_warnings(warnings)
    _print_check(run, args.verbose)
    html_path = report.write_report(run.out_dir)
    c = run.counts()
    kept = any(r["files"] for r in run.results)       # only failures leave images
    print("golden check: %d passed, %d failed, %d missing, %d errors; %sreport %s"
          % (c["pass"], c["fail"], c["missing"], c["error"],
             "images of failures in %s; " % _show(run.out_dir) if kept else "", _show(html_path)))
    if args.timings:
        print(_timings(run.results))
    return 0 if run.ok else 1


def _timings(results):
    from mtlxgen.apps.batch import timing_table
    return timing_table([(r["name"], r["timings"], r["status"] != "error") for r in results])


def cmd_golden_update(args):
    from mtlxgen.apps import golden
    from mtlxgen.apps.batch import RenderSettings
    settings = None
    if args.size is not None or args.env is not None:
        settings = RenderSettings(size=args.size or RenderSettings.size,
                                  environment=os.path.abspath(args.env) if args.env else RenderSettings.environment)
    warnings = []
    done = golden.update(args.paths, args.goldens, settings, workers=args.workers,
                         progress=False if args.no_progress else None, warnings=warnings, options=_options(args),
                         scheduler=args.scheduler)
    _print_warnings(warnings)
    status = 0
    for name, what, lines in done:
        if what != "unchanged" or args.verbose:
            print("%-9s %s" % (what, name))
        for line in lines if what == "error" else ():
            print("          " + line)
        status = 1 if what == "error" else status
    counts = {}
    for _, what, _ in done:
        counts[what] = counts.get(what, 0) + 1
    print("golden update: %s in %s" % (", ".join("%d %s" % (v, k) for k, v in sorted(counts.items())) or "nothing",
                                        _show(args.goldens)))
    return status


def cmd_report(args):
    from mtlxgen.apps import golden, report
    out = args.dir
    if not os.path.lexists(os.path.join(out, "results.json")):
        # a directory of materials: check it first, into --checks (a dangling results.json: report refuses it)
        warnings = []
        run = golden.check([out], args.goldens or golden.DEFAULT_DIR, args.checks, workers=args.workers,
                           progress=False if args.no_progress else None, warnings=warnings,
                           options=_options(args))
        _print_warnings(warnings)
        out = run.out_dir
    path = report.write_report(out, args.output)
    print(path)
    return 0


def cmd_batch(args):
    from mtlxgen.apps import batch
    from mtlxgen.base import images
    from mtlxgen.apps.batch import RenderSettings
    settings = RenderSettings(size=args.size, environment=os.path.abspath(args.env) if args.env else "builtin_sky")
    skipped = []            # entries that cannot be read (dangling links, FIFOs, ...): reported, the rest done
    jobs = [batch.Job(path, (element,) if element else (), settings)
            for path, element in map(batch.split_spec, batch.find_materials(args.paths, skipped))]
    for line in MtlxError(skipped).lines():
        print(line, file=sys.stderr)
    items = batch.render_jobs(jobs, workers=args.workers,
                              progress=False if args.no_progress else None, options=_options(args),
                              post=batch.srgb8_drawn,
                              scheduler=args.scheduler)
    _print_warnings(line for it in items for line in it.warnings)
    status, printed, written = (1 if skipped else 0), set(), {}
    for it in items:
        for line in it.error:           # failures, and problems of elements still drawn (USD: missing textures)
            status = 1
            if line not in printed:
                printed.add(line)
                print(line, file=sys.stderr)
        if not it.ok:
            status = 1
            continue
        from mtlxgen.apps.golden import golden_name
        out = os.path.join(args.output, golden_name(it.path, it.element) + ".png")
        if written.setdefault(out, it.path) != it.path:       # a/x.mtlx and b/x.mtlx: never one over the other
            status = 1
            print("%s:1: image %s is also drawn from %s; not written (rename one of the files)"
                  % (it.path, os.path.basename(out), written[out]), file=sys.stderr)
            continue
        try:                            # one image that cannot be written: said, and the others written
            images.write_image(out, it.outcome["srgb8"])
        except MtlxError as e:
            status = 1
            print("\n".join(e.lines()), file=sys.stderr)
        except OSError as e:
            status = 1
            print("%s:0: cannot write image: %s" % (out, e.strerror or e), file=sys.stderr)
    print(batch.timing_table([("%s:%s" % (it.path, it.element), it.timings, it.ok) for it in items]))
    return status


def _scheduler(text):
    from mtlxgen.apps.cluster import check_address
    try:
        return check_address(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def _shard(text):
    k, _, n = text.partition("/")
    if not (k.isdigit() and n.isdigit() and 1 <= int(k) <= int(n) <= 100000):
        raise argparse.ArgumentTypeError("%r is not K/N: the K-th of N shards, 1 <= K <= N" % text)
    return int(k), int(n)


def cmd_golden_report(args):
    from mtlxgen.apps import report
    merged = report.merge_shards(args.shards, args.output)
    c = {k: sum(1 for r in merged["results"] if r["status"] == k) for k in ("pass", "fail", "missing", "error")}
    for note in merged["notes"]:
        print("note: " + note, file=sys.stderr)
    html_path = report.write_report(args.output)
    print("golden report: %d shard%s, %d passed, %d failed, %d missing, %d errors; report %s"
          % (len(args.shards), "" if len(args.shards) == 1 else "s", c["pass"], c["fail"], c["missing"], c["error"],
             _show(html_path)))
    return 0 if merged["complete"] and c["pass"] == len(merged["results"]) else 1


COMMANDS = ("generate", "render", "info", "view", "web", "three", "golden", "report", "batch")


def build_parser(command=None):
    """The command line's parser; with `command` (the first argument, a command's name), only that command's
    subparser is built (what it parses and prints is the same: each command parses its own arguments)."""
    if command not in COMMANDS:         # --help, or no such command: every command (listed, or offered)
        command = None
    ap = _Parser(prog="mtlxgen", description="MaterialX documents to GLSL shaders")
    ap.add_argument("--version", action=_Version, nargs=0, help="print mtlxgen's version and exit")
    sub = ap.add_subparsers(dest="command", metavar="COMMAND", required=True)

    def shader_interface(p, default="complete"):
        p.add_argument("--interface", choices=("complete", "reduced"), default=None,
                       help="complete = every public input a uniform named as MaterialX names it; reduced = "
                            "unconnected inputs become constants and what they make constant is computed at "
                            "generation time (inputs marked uniform=\"true\" and those named by --keep stay uniforms) "
                            "(default: %s)" % default)
        p.add_argument("--keep", action="append", default=[], metavar="NAME",
                       help="reduced interface: keep this input a uniform (repeatable): its uniform name as the "
                            "complete manifest lists it, or NODE/INPUT; a name that names nothing is an error")
        p.add_argument("--keep-file", metavar="FILE", type=_readable_file,
                       help="reduced interface: names to keep uniforms, one a line or a JSON list (or a manifest "
                            "of ours: its kept inputs, else its uniforms)")

    def output_dir_and_element(p):
        p.add_argument("-o", "--output", required=True, metavar="DIR", type=_output_dir)
        p.add_argument("--element", metavar="NAME", type=_name,
                       help="only this element (name path; for a USD stage, a material's prim path or name)")

    def generation(p):
        """Options of how shaders are generated (_options), for every command that generates."""
        shader_interface(p)
        p.add_argument("--max-lights", type=_int_in(0, LIGHTS_LIMIT), default=None, metavar="N",
                       help="lit surfaces loop over up to N direct lights bound to u_lightData[] (0 to %d; default 0: "
                            "no light loop, the environment alone; render --lights: the rig's count)" % LIGHTS_LIMIT)
        p.add_argument("--target", choices=TARGET_NAMES, default="glsl",
                       help="shading language: glsl = desktop GLSL 4.00 (default), essl = GLSL ES 3.00 for WebGL2 "
                            "(no uniform initializers: the manifest's values and \"application\" defaults are bound), "
                            "vulkan = GLSL 4.50 for SPIR-V (one std140 uniform block, bindings and locations in the "
                            "manifest)")

    def common(p):
        p.add_argument("file", help="a .mtlx document or a USD stage (.usd, .usda, .usdc, .usdz)")
        p.add_argument("--library", action="append", default=[], metavar="DIR", type=_existing_dir,
                       help="extra directory of .mtlx definitions (repeatable)")
        p.add_argument("--usd-seed-rules", action=argparse.BooleanOptionalAction, default=None,
                       help="USD preview nodes follow the UsdPreviewSurface seed's rules rather than MaterialX's "
                            "nodegraphs (default: on for documents from USD: USD's preview nodes in USD's own "
                            "vocabulary, e.g. a `result` output or `sourceColorSpace`)")
        p.add_argument("--environment", choices=ENVIRONMENT_METHODS, default="fis",
                       help="how environment light is integrated: fis = filtered importance sampling with "
                            "u_envRadianceSamples samples (default), prefiltered = one lookup in the mip chain "
                            "per lobe at a roughness-chosen level (split sum; faster, blurrier)")
        p.add_argument("--variant", action="append", default=[], metavar="SET=NAME", type=_variant,
                       help="USD stages: select variant NAME of variant set SET wherever the set is (repeatable)")
        p.add_argument("--render-context", choices=("mtlx", "universal"), default=None,
                       help="USD stages: which surface a material with both outputs:mtlx:surface and "
                            "outputs:surface draws (default: mtlx)")
        p.add_argument("--strict", action="store_true",
                       help="make each warning an error: a document MaterialX reads with a slip in it (a value with "
                            "text after its number, a color3 input fed by a vector3, an input its nodedef lacks) is "
                            "reported and that element not written (default: read as MaterialX reads it, warned)")

    if command in (None, "generate"):
        p = sub.add_parser("generate", help="write NAME.vert, NAME.frag, NAME.json per renderable element")
        common(p)
        generation(p)
        output_dir_and_element(p)
        talk = p.add_mutually_exclusive_group()
        talk.add_argument("-v", "--verbose", action="store_true", help="print each path written")
        talk.add_argument("-q", "--quiet", action="store_true",
                          help="print nothing but problems (default: one `wrote DIR/NAME.{vert,frag,json}` line an "
                               "element)")
        p.add_argument("--absolute-paths", action="store_true",
                       help="texture files in NAME.json as absolute paths (default: relative to NAME.json's folder)")
        p.set_defaults(func=cmd_generate)

    if command in (None, "render"):
        p = sub.add_parser("render", help="render each element on a sphere to NAME.png (sRGB) and NAME.exr (linear)")
        common(p)
        generation(p)
        output_dir_and_element(p)
        p.add_argument("--size", type=_int_in(1, MAX_SIZE), default=256, metavar="N",
                       help="image width and height in pixels, 1 to %d (default: 256)" % MAX_SIZE)
        p.add_argument("--env", metavar="FILE", type=_readable_file,
                       help="lat-long HDR/EXR environment (default: built-in sky)")
        p.add_argument("--lights", metavar="RIG.mtlx", type=_readable_file,
                       help="bind a light-rig document's point/directional/spot lights to u_lightData")
        p.add_argument("--geometry", choices=("sphere", "stage"), default="sphere",
                       help="stage (USD stages): also draw the stage's own meshes with their materials, from its "
                            "camera or a framing one, to DIR/STEM__stage.png (default: the sphere per material only)")
        p.set_defaults(func=cmd_render)

    if command in (None, "info"):
        p = sub.add_parser("info", help="list elements, their nodes and unresolved problems")
        common(p)
        p.set_defaults(func=cmd_info)

    if command in (None, "view"):
        p = sub.add_parser("view", help="a live window drawing the document's elements, redrawn as it is edited")
        common(p)
        shader_interface(p, default="specialized: reduced, every input a uniform but those at zero, each kept "
                                    "once moved off zero")
        p.add_argument("--element", metavar="NAME", type=_name, help="the element to show first (Tab cycles them)")
        p.add_argument("--env", metavar="FILE", type=_readable_file,
                       help="lat-long HDR/EXR environment (default: built-in sky)")
        p.add_argument("--lights", metavar="RIG.mtlx", type=_readable_file,
                       help="bind a light-rig document's point/directional/spot lights (L toggles them)")
        p.add_argument("--geometry", type=_geometry, default="sphere", metavar="SHAPE",
                       help="sphere (default, render's), plane, cube, shaderball, or a mesh file (OBJ, PLY, glTF, ...)")
        p.add_argument("--size", type=_int_in(1, MAX_SIZE), nargs=2, default=(512, 512), metavar=("W", "H"),
                       help="window size in pixels (default: 512 512)")
        p.add_argument("--samples", type=_samples, default=256, metavar="N",
                       help="environment samples of the converged picture, a power of two (default: 256; S steps "
                            "through 16 .. 4096)")
        p.add_argument("--frame-samples", type=_samples, default=16, metavar="N",
                       help="samples per accumulated frame while the camera is still (default: 16)")
        p.add_argument("--no-progressive", action="store_true",
                       help="draw all --samples in every frame instead of accumulating frames")
        p.add_argument("--background", action=argparse.BooleanOptionalAction, default=True,
                       help="draw the environment behind the object (B toggles it; default: on)")
        p.add_argument("-o", "--output", default=".", metavar="DIR", type=_output_dir,
                       help="where screenshots (key C) go, named as render names them (default: .)")
        p.add_argument("--headless-frames", type=_int_in(1, 1000000), default=None, metavar="N",
                       help="draw N frames and exit: in a window where a display is (Xvfb too), else offscreen")
        p.add_argument("--screenshot", type=_output_file, default=None, metavar="FILE",
                       help="with --headless-frames: write the last frame to FILE (.png; and .exr beside it)")
        p.add_argument("--capture-window", type=_output_file, default=None, metavar="FILE",
                       help="with --headless-frames: also write what the window shows (panel included) to FILE.png")
        p.add_argument("--no-watch", action="store_true", help="do not reload when the files change (R reloads)")
        p.add_argument("--no-panel", action="store_true", help="no property panel")
        p.set_defaults(func=cmd_view)

    def web_options(p, what):
        common(p)
        shader_interface(p)
        output_dir_and_element(p)
        p.add_argument("--env", metavar="FILE", type=_readable_file,
                       help="lat-long HDR/EXR environment %s (default: built-in sky)" % what)
        p.add_argument("--size", type=_int_in(1, MAX_SIZE), default=256, metavar="N",
                       help="canvas width and height in pixels, 1 to %d (default: 256, as render)" % MAX_SIZE)
        p.add_argument("--samples", type=_int_in(1, 65536), default=64, metavar="N",
                       help="environment samples per lobe, u_envRadianceSamples (default: 64, as render)")
        p.set_defaults(target="essl")

    if command in (None, "web"):
        p = sub.add_parser("web", help="a self-contained WebGL2 page per element (NAME.html): render's sphere, camera "
                                       "and environment, orbit controls; works opened from file://")
        web_options(p, "embedded in the page")
        p.set_defaults(func=cmd_web)

    if command in (None, "three"):
        p = sub.add_parser("three", help="a three.js ES module per element (NAME.js: createMaterial(THREE) returns a "
                                         "RawShaderMaterial), the shared mtlxgen_three.js, an example page NAME.html")
        web_options(p, "the example pages light with (written as environment.exr)")
        p.set_defaults(func=cmd_three)

    def pool(p):
        p.add_argument("-j", "--workers", type=_int_in(1, MAX_WORKERS), default=None, metavar="N",
                       help="render processes, 1 to %d (default: one per core)" % MAX_WORKERS)
        p.add_argument("--no-progress", action="store_true", help="no progress bar on stderr")
        generation(p)
        p.add_argument("--library", action="append", default=[], metavar="DIR", type=_existing_dir,
                       help="extra directory of .mtlx definitions (repeatable)")
        p.add_argument("--strict", action="store_true",
                       help="make each warning an error: a document MaterialX reads with a slip in it (a value with "
                            "text after its number, a color3 input fed by a vector3, an input its nodedef lacks) is "
                            "reported and that element not written (default: read as MaterialX reads it, warned)")

    def scheduler(p):
        p.add_argument("--scheduler", type=_scheduler, default=None, metavar="ADDRESS",
                       help="draw (and compare) on a Dask cluster: tcp://HOST:PORT of a running scheduler, or local:N "
                            "for N worker processes here; workers read inputs at the same paths (docs/cluster.md)")

    if command in (None, "golden"):
        p = sub.add_parser("golden",
                           help="golden-image regression: check renders against golden_images/, or update them")
        gsub = p.add_subparsers(dest="golden_command", metavar="{check,update,report}", required=True)
        g = gsub.add_parser("check", help="render and compare with the goldens; exit 1 on any difference")
        g.add_argument("paths", nargs="*", metavar="PATH",
                       help=".mtlx files, USD stages, directories (searched for both), or FILE:ELEMENT (default: every "
                            "golden in the index)")
        g.add_argument("--goldens", default=None, metavar="DIR", type=_existing_dir,
                       help="golden directory (default: golden_images)")
        g.add_argument("-o", "--output", default=os.path.join("out", "golden"), metavar="DIR", type=_output_dir,
                       help="where results.json, report.html and the new/golden/diff images of failures go "
                            "(default: out/golden)")
        g.add_argument("--threshold", type=_int_in(0, 255), default=2, metavar="STEPS",
                       help="8-bit sRGB steps a pixel may differ by, 0 to 255 (default: 2)")
        g.add_argument("--max-fraction", type=_float_in(0.0, 1.0), default=0.0, metavar="F",
                       help="share of pixels allowed over the threshold, 0 to 1 (default: 0)")
        g.add_argument("--flip-limit", type=_float_in(0.0, 1.0), default=None, metavar="F",
                       help="also fail when the mean FLIP error (0 to 1) exceeds F (default: FLIP is reported only)")
        g.add_argument("--no-flip", action="store_true", help="skip the FLIP score")
        g.add_argument("--timings", action="store_true", help="print per-material timings")
        g.add_argument("-v", "--verbose", action="store_true", help="list passing materials too")
        g.add_argument("--shard", type=_shard, default=None, metavar="K/N",
                       help="check the K-th of N shards of the elements (by a hash of each one's source and element: "
                            "stable as documents come and go); merge the shards' outputs with `golden report`")
        pool(g)
        scheduler(g)
        g.set_defaults(func=cmd_golden_check)
        g = gsub.add_parser("update", help="render and rewrite goldens (and their index entries)")
        g.add_argument("paths", nargs="*", metavar="PATH",
                       help=".mtlx files, USD stages, directories (searched for both), or FILE:ELEMENT (default: every "
                            "golden in the index)")
        g.add_argument("--goldens", default="golden_images", metavar="DIR", type=_output_dir)
        g.add_argument("--size", type=_int_in(1, MAX_SIZE), default=None, metavar="N",
                       help="image size, 1 to %d (default: what each golden recorded, else 128)" % MAX_SIZE)
        g.add_argument("--env", metavar="FILE", type=_readable_file,
                       help="lat-long HDR/EXR environment (default: recorded, else built-in sky)")
        g.add_argument("-v", "--verbose", action="store_true", help="list unchanged goldens too")
        pool(g)
        scheduler(g)
        g.set_defaults(func=cmd_golden_update)
        g = gsub.add_parser("report", help="merge the outputs of `golden check --shard K/N` runs into one "
                                           "results.json and report; exit 1 unless every element passed")
        g.add_argument("shards", nargs="+", metavar="DIR", type=_existing_dir,
                       help="`golden check` output directories (one per shard)")
        g.add_argument("-o", "--output", required=True, metavar="DIR", type=_output_dir,
                       help="where the merged results.json, the failures' images and report.html go")
        g.set_defaults(func=cmd_golden_report)

    if command in (None, "report"):
        p = sub.add_parser("report", help="one self-contained HTML page from a golden check's output directory")
        p.add_argument("dir", metavar="DIR", type=_existing_dir,
                       help="a `golden check` output directory (or a directory of .mtlx documents and USD stages to "
                            "check)")
        p.add_argument("-o", "--output", metavar="FILE", type=_output_file, help="HTML file (default: DIR/report.html)")
        p.add_argument("--goldens", default=None, metavar="DIR", type=_existing_dir,
                       help="golden directory (default: golden_images)")
        p.add_argument("--checks", default=os.path.join("out", "golden"), metavar="DIR", type=_output_dir,
                       help="where to check a directory of materials first (default: out/golden)")
        pool(p)
        p.set_defaults(func=cmd_report)

    if command in (None, "batch"):
        p = sub.add_parser("batch", help="render every .mtlx document and USD stage under directories with all cores; "
                                              "print per-material timings")
        p.add_argument("paths", nargs="+", metavar="PATH",
                       help="directories (searched for .mtlx documents and USD stages), files, or FILE:ELEMENT")
        p.add_argument("-o", "--output", required=True, metavar="DIR", type=_output_dir)
        p.add_argument("--size", type=_int_in(1, MAX_SIZE), default=128, metavar="N",
                       help="image size, 1 to %d (default: 128)" % MAX_SIZE)
        p.add_argument("--env", metavar="FILE", type=_readable_file,
                       help="lat-long HDR/EXR environment (default: built-in sky)")
        pool(p)
        scheduler(p)
        p.set_defaults(func=cmd_batch)
    return ap


# the modules mtlxgen imports from other distributions, and the package pip installs each from
PIP_PACKAGES = {"moderngl": "moderngl", "numpy": "numpy", "OpenImageIO": "OpenImageIO", "MaterialX": "materialx",
                "pxr": "usd-core", "flip_evaluator": "flip-evaluator", "glfw": "glfw", "imgui_bundle": "imgui-bundle",
                "watchdog": "watchdog", "trimesh": "trimesh"}


def _missing_package(error):
    """The pip package of a module an ImportError could not import (None: not one of our dependencies)."""
    name = (getattr(error, "name", None) or "").split(".")[0]
    return PIP_PACKAGES.get(name)


class _Version(argparse.Action):
    """--version: the installed distribution's version (looked up only when asked: importlib.metadata is slow)."""

    def __call__(self, parser, namespace, values, option_string=None):
        import mtlxgen
        print("mtlxgen %s" % mtlxgen.__version__)
        parser.exit(0)


def main(argv=None):
    try:
        argv = sys.argv[1:] if argv is None else argv
        args = build_parser(argv[0] if argv else None).parse_args(argv)
    except SystemExit as e:            # --help (0) or a usage error (1, already printed): a status, not an exception
        return e.code
    try:
        if getattr(args, "file", None) is not None:
            _check_document(args.file)
        return args.func(args)
    except MtlxError as e:
        return _report(e)
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:            # output piped into a reader that stopped early (e.g. `| head`)
        try:
            sys.stdout = open(os.devnull, "w")
        except OSError:
            pass
        return 0
    except RecursionError:
        if os.environ.get("MTLXGEN_DEBUG"):
            raise
        print("%s: error: the document nests too deeply to process" % getattr(args, "file", "mtlxgen"), file=sys.stderr)
        return 1
    except Exception as e:     # a bug of ours: one line, the traceback only on request
        package = _missing_package(e) if isinstance(e, ImportError) else None
        if package is not None:         # a dependency that is not installed: which package to install, one line
            print("mtlxgen %s: error: the Python package %s is not installed (pip install %s)"
                  % (getattr(args, "command", ""), package, package), file=sys.stderr)
            return 1
        if os.environ.get("MTLXGEN_DEBUG"):
            raise
        if isinstance(e, OSError) and e.filename:
            # the file system refused (disk full, permissions changed since the options were checked)
            print("%s:0: %s" % (e.filename, e.strerror or e), file=sys.stderr)
            return 1
        print("%s: internal error: %s: %s (set MTLXGEN_DEBUG=1 for details)"
              % (getattr(args, "file", "mtlxgen"), type(e).__name__, e), file=sys.stderr)
        return 3


if __name__ == "__main__":
    sys.exit(main())
