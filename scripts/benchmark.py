#!/usr/bin/env python3
"""Runs shipped fine scenes with the Release build and prints a table.

Usage: scripts/benchmark.py [SCENE ...]   (default: every benchmark below)

Each benchmark is a shipped prm file plus --set overrides. VTU output is
switched off. The table (Markdown) shows grid, DoFs, linear solver, Newton
iterations, preconditioner setups (multigrid hierarchies or Cholesky
factorizations), time per Newton iteration, total time and peak memory, all
read from each run's summary.json. It is a benchmark, not a test: timings depend
on the machine and its load.
"""
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BENCHMARKS = {
    "pushing": ("pushing", []),
    "bending": ("bending", []),
    "twisting": ("twisting", []),
    "buckling": ("buckling", []),
    "fibers": ("fibers", []),
    "bar": ("bar", []),
    "bar-32": ("bar", ["Geometry/Grid size=32, 128, 32",
                       "Geometry/Voxel size=0.03125",
                       "Geometry/Probe points=0.5, 4, 0.5"]),
}
# Per Newton iteration on the same bar (1x4x1, Q1, layers 1e5/1e7, body
# force, Newton to 1e-8): a plain deal.II solver with Trilinos ML AMG-CG,
# measured on this machine class (issue #2).
REFERENCE = {"bar": 2.0, "bar-32": 17.7}
BINARY = os.path.join(ROOT, "build", "ddfem")


def run(name):
    """Runs benchmark @p name; its exit code and its summary.json (None if
    it wrote none)."""
    prm, overrides = BENCHMARKS[name]
    out = os.path.join(ROOT, "benchmark-output", name)
    os.makedirs(out, exist_ok=True)
    summary_file = os.path.join(out, "summary.json")
    # A run that stops on its input checks writes nothing: the summary of an
    # earlier run must not stand in for it.
    if os.path.exists(summary_file):
        os.remove(summary_file)
    command = [BINARY, os.path.join(ROOT, "prm", prm + ".prm"),
               "--set", "Output/Output directory=" + out,
               "--set", "Output/Write VTU=none"]
    for o in overrides:
        command += ["--set", o]
    with open(out + ".log", "w") as log:
        code = subprocess.call(command, stdout=log, stderr=subprocess.STDOUT)
    # Exit code 1 with a summary: a solve that did not converge, which the
    # table shows. No summary (a run killed for memory, an input error):
    # None, and the queue goes on.
    try:
        with open(summary_file) as f:
            return code, json.load(f)
    except (OSError, ValueError):
        return code, None


def main():
    if len(sys.argv) > 1 and sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return
    names = sys.argv[1:] or list(BENCHMARKS)
    unknown = [n for n in names if n not in BENCHMARKS]
    if unknown:
        sys.exit(f"Error: unknown benchmark {', '.join(unknown)}; the benchmarks "
                 f"are {', '.join(BENCHMARKS)}.")
    if not os.access(BINARY, os.X_OK):
        sys.exit(f"Error: no {BINARY}; build first (bash scripts/setup.sh).")
    cache = os.path.join(ROOT, "build", "CMakeCache.txt")
    try:
        with open(cache) as f:
            release = "CMAKE_BUILD_TYPE:STRING=Release\n" in f.read()
    except OSError:
        release = False
    if not release:
        sys.exit("Error: build/ is not a Release build "
                 "(scripts/setup.sh makes one).")
    failed = []
    print("| scene | grid | DoFs | solver | load steps | Newton its | setups "
          "| s / Newton it | total s | peak MiB | reference s / it |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name in names:
        code, s = run(name)
        if s is None:
            failed.append(name)
            print(f"| {name} (exit code {code}, no readable summary.json) "
                  "| | | | | | | | | | |", flush=True)
            continue
        ref = REFERENCE.get(name)
        per_iteration = s["time_per_iteration_s"]
        ref_text = "%.1f (ratio %.2f)" % (ref, per_iteration / ref) if ref else ""
        # A run that did not converge, or that ended with an error after
        # its summary, fails the benchmark.
        status = ""
        if not s["converged"]:
            status = " (NOT converged)"
        elif code != 0:
            status = " (exit code %d)" % code
        if status:
            failed.append(name)
        print("| %s%s | %s | %d | %s | %d | %d | %d | %.3f | %.1f | %.0f | %s |" % (
            name, status,
            "x".join(str(n) for n in s["grid"]), s["dofs"], s["linear_solver"],
            s["load_steps"], s["newton_iterations"],
            s["preconditioner_setups"], per_iteration,
            s["wall_time_s"], s["peak_memory_mb"], ref_text), flush=True)
    if failed:
        sys.exit(f"Error: benchmarks that failed: {', '.join(failed)}; see "
                 f"benchmark-output/<name>.log.")


if __name__ == "__main__":
    main()
