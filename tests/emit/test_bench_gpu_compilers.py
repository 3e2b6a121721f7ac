"""benchmarks/bench_gpu_compilers.py: real GPU compilers (Mesa's RADV/ACO, nouveau) on no GPU, ours against
MaterialX's. Runs on one element with one backend where ../shared/tools/gpu_proxy's setup is installed
(`bash ../shared/tools/gpu_proxy/setup.sh`) and skips with the reason otherwise; without the tools it must say
the one setup command and exit 1."""
import os
import re
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(ROOT, "benchmarks", "bench_gpu_compilers.py")
sys.path.insert(0, os.path.join(ROOT, "benchmarks"))

import bench_gpu_compilers  # noqa: E402

CELL = re.compile(r"(\S+)/(\S+?)(?:=(\S+))?$")


def _run(*args, env=None):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True, cwd=ROOT, timeout=900,
                          env=dict(os.environ, **(env or {})))


def test_without_the_tools_it_names_the_setup_command(tmp_path):
    p = _run("--only", "gltf_pbr_default", env={"GPUPROXY_PREFIX": str(tmp_path)})
    assert p.returncode == 1, p.stdout + p.stderr
    lines = p.stdout.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("bench_gpu_compilers: "), p.stdout + p.stderr
    assert "Traceback" not in p.stderr
    if os.path.exists(os.path.join(bench_gpu_compilers.GPU_PROXY, "measure.py")):
        assert "bash ../shared/tools/gpu_proxy/setup.sh" in lines[0] and str(tmp_path) in lines[0]


def test_one_element_on_radv_aco():
    why = bench_gpu_compilers.missing_tools()
    if why:
        pytest.skip(why)
    pytest.importorskip("MaterialX", reason="MaterialX's side needs the 'materialx' wheel")
    p = _run("--only", "gltf_pbr_default", "--backends", "radv-aco")
    assert p.returncode == 0, p.stdout + p.stderr
    lines = p.stdout.strip().splitlines()
    rows = {}
    for line in lines:
        f = line.split()
        if f[0].startswith("gltf_pbr_default:") and f[1] == "radv-aco":
            rows[f[2]] = dict(zip(bench_gpu_compilers.COLUMNS, f[3:]))
    assert set(rows) == {"complete", "reduced"}, p.stdout
    instr = {}
    for mode, cells in rows.items():
        for column in ("cpu", "instr", "regs"):
            m = CELL.match(cells[column])
            assert m and m.group(3), (mode, column, cells)
            ours, theirs, ratio = (float(g) for g in m.groups())
            assert ours > 0 and theirs > 0 and abs(ratio - ours / theirs) < 0.011 + 0.01 * ratio, (mode, column, cells)
        instr[mode] = int(CELL.match(cells["instr"]).group(1))
    # the reduced interface folds the unconnected inputs: far fewer instructions than the complete shader
    assert instr["reduced"] < instr["complete"] / 2, instr
    last = lines[-1]
    assert last.startswith("overall ours / MaterialX (totals): radv-aco complete: cpu "), last
    assert re.search(r"radv-aco reduced: cpu \d+\.\d\d, instr \d+\.\d\d, regs \d+\.\d\d", last), last


def test_a_baseline_that_is_no_project_copy_is_one_line(tmp_path):
    p = _run("--baseline", str(tmp_path), "--only", "gltf_pbr_default")
    assert p.returncode == 1 and "Traceback" not in p.stderr, p.stdout + p.stderr
    assert p.stdout.strip() == ("bench_gpu_compilers: --baseline %s: no mtlxgen/ there (a copy of the project is "
                                "needed)" % tmp_path), p.stdout
