"""`mtlxgen info SCENE.usd`: what a USD stage's materials became (usdstage.py read through pipeline.Session)."""
import os
import sys

from mtlxgen import pipeline
from mtlxgen.base.diagnostics import MtlxError


def print_info(path, options=None, out=None):
    """`mtlxgen info SCENE.usd`: each material with its prim, the surface drawn, its shaders and their
    ids, its graph, and what could not be resolved. options: an options.GenerateOptions (library_dirs,
    usd_seed_rules, variants, render_context, strict). Returns the exit status (1 where anything was not)."""
    out = out or sys.stdout
    session = pipeline.Session(path, options)
    stage = session.stage
    opts = stage.options
    print("%s (USD stage: %d material%s; render context %s%s)"
          % (path, len(stage.materials), "" if len(stage.materials) == 1 else "s", opts.render_context,
             "; variants " + ", ".join("%s=%s" % v for v in opts.variants) if opts.variants else ""), file=out)
    status = 1 if stage.problems else 0
    for name, m in stage.materials.items():
        how = ("from %s" % os.path.relpath(m.source) if m.source else
               "%s surface" % m.context if m.context else "no surface")
        if len(m.contexts) > 1:
            how += " (also: %s)" % ", ".join(c for c in m.contexts if c != m.context)
        print("  %s  <%s>  %s" % (name, m.prim, how), file=out)
        for prim, sid in m.shaders:
            print("    %-44s %s" % (prim, sid), file=out)
        unresolved = list(m.problems)
        if not m.problems:
            try:
                g = session.graph(name)
                print("    graph: %d nodes, %d uniforms" % (len(g.nodes), len(g.uniforms)), file=out)
            except MtlxError as e:
                unresolved += e.problems
        unresolved += m.notes
        if unresolved:
            status = 1
            print("    unresolved:", file=out)
            for line in MtlxError(unresolved).lines():
                print("      " + line, file=out)
        if m.ignored:
            print("    ignored:", file=out)
            for line in MtlxError(m.ignored).lines():
                print("      " + line, file=out)
    if stage.problems:
        print("  stage:", file=out)
        for line in MtlxError(stage.problems).lines():
            print("    " + line, file=out)
    return status
