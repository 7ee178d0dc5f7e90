#!/usr/bin/env python3
"""Summarize the compare runs of the shipped scenes against the issue's targets.

Reads DIR/<scene>/comparison.json, as written by 'Run type = compare'
(scripts/compare_scenes.sh writes them to output/compare), and prints

- one Markdown table row per scene state: unknowns, the fastest fine run, the
  fine direct run, ddfem's speedups and every model's mean vertex error at
  levels 1 and 2, the level-1 grid bound, ddfem's largest coarsening time and
  the compare run's peak memory (the table of doc/coarsening.md);
- each target of the coarsening issue with the states that meet it and those
  that miss it; a scene's own targets (30x at level 2, the paper's error) go
  by the scene name in comparison.json. The half-of-naive target is meant for
  heterogeneous parts; the script lists every state, so a state of one
  material (the character's base state) is listed too.

Speedups divide the wall time of the fastest fine run that converged ('fine',
'fine-amg' where the scene's solver is another one, or 'fine-direct') by the
coarse model's, as the compare run does; the speedup against the fine run with
the direct solver (UMFPACK: 'fine-direct', or 'fine' where the scene's solver
is direct) is shown in parentheses where it ran. A value the compare run left
null (the errors of a run that did not converge, or of every run when the fine
model did not) is shown as '-', and the targets skip it; so do the speedup
targets of a state without a converged fine run.

  python3 scripts/compare_table.py                     # the repository's output/compare, every scene found
  python3 scripts/compare_table.py DIR bending bridge  # some scenes
"""

import json
import os
import sys

# The shipped scenes that have a compare run, in the order of the table:
# scripts/compare_scenes.sh's nine, then the mechanism blocks of lattice,
# which it runs only when named.
SCENES = ["pushing", "bending", "twisting", "buckling", "fibers", "bridge",
          "bridge_arch", "shoe_sole", "character", "lattice"]

# The paper's Table 1: ddfem's level-1 mean vertex error per scene.
PAPER_L1_ERROR = {"pushing": 8.9e-4, "bending": 5.6e-2, "twisting": 1.6e-2,
                  "buckling": 7.2e-3, "fibers": 2.9e-2}

# The targets of the coarsening issue, in the order they are printed.
L1_SPEED = "ddfem L1 at least 8x faster than the fastest fine run"
L2_SPEED = "ddfem L2 at least 30x faster on buckling and fibers, 15x elsewhere"
TABLE_1 = "ddfem L1 error at or below the paper's Table 1"
HALF_NAIVE = "ddfem L1 error at most half of naive's"
L2_ERROR = "ddfem L2 error below naive L2"
COARSENING = "coarsening below 50 ms"
TARGETS = [L1_SPEED, TABLE_1, HALF_NAIVE, L2_SPEED, L2_ERROR, COARSENING]

# Level-2 speedup targets; every other scene has 15x.
L2_SPEEDUP = {"buckling": 30., "fibers": 30.}


# The keys the table reads from every run of a comparison.json, with the types
# a compare run writes for them (None where it may leave a value null; a
# coarse run's coarsening_time_s and, next to a converged fine run, a
# converged run's speedup_vs_fine are never null: load_states checks them).
NUMBER = (int, float)
OR_NULL = (int, float, type(None))
RUN_KEYS = {"state": (str,), "method": (str,), "level": (int,), "dofs": (int,),
            "converged": (bool,), "wall_time_s": NUMBER, "linear_solver": (str,),
            "newton_iterations": (int,), "speedup_vs_fine": OR_NULL,
            "speedup_vs_fine_direct": OR_NULL, "mean_vertex_error": OR_NULL,
            "grid_fit_lower_bound": OR_NULL, "coarsening_time_s": OR_NULL}


def well_typed(x, types):
    """Whether @p x has one of @p types (a bool is no number here)."""
    return isinstance(x, types) and (bool in types or not isinstance(x, bool))


def load_states(directory, scene):
    """The runs of DIR/scene/comparison.json grouped by state, in file order.

    Exits with a message naming the file if it cannot be read or lacks what a
    compare run writes (a run killed while writing it, say, or a null that a
    compare run does not leave)."""
    file = os.path.join(directory, scene, "comparison.json")
    try:
        with open(file) as f:
            data = json.load(f)
        if not well_typed(data.get("peak_memory_mb"), NUMBER) or \
                not isinstance(data.get("runs"), list) or not data["runs"]:
            raise ValueError("no runs or no peak_memory_mb")
        # The scene's targets go by the name the compare run wrote, which
        # holds where the directory was renamed.
        if not isinstance(data.get("scene", scene), str):
            raise ValueError("its scene is not of the type a compare run writes")
        states = {}
        for run in data["runs"]:
            missing = [k for k in RUN_KEYS if k not in run]
            if missing:
                raise ValueError(f"a run has no {', '.join(missing)}")
            wrong = [k for k, types in RUN_KEYS.items()
                     if not well_typed(run[k], types)]
            if wrong:
                raise ValueError(f"a run's {', '.join(wrong)} is not of the "
                                 "type a compare run writes")
            if run["level"] > 0 and run["coarsening_time_s"] is None:
                raise ValueError(f"the coarse run {run['method']} L{run['level']} "
                                 f"of state {run['state']} has a null "
                                 "coarsening_time_s")
            states.setdefault(run["state"], []).append(run)
        # A compare run divides by the fastest converged fine run, so each
        # converged run of a state that has one has a speedup.
        for state, runs in states.items():
            if not any(r["level"] == 0 and r["converged"] for r in runs):
                continue
            for r in runs:
                if r["converged"] and r["speedup_vs_fine"] is None:
                    raise ValueError(f"the converged run {r['method']} L{r['level']} "
                                     f"of state {state} has a null speedup_vs_fine "
                                     "next to a converged fine run")
    except (OSError, ValueError, AttributeError, TypeError) as error:
        sys.exit(f"Error: {file} is not a compare run's comparison.json ({error}); "
                 "run the scene's compare run again.")
    return data, states


def find(runs, method, level):
    """The run of one method at one level, or None if the compare run had none."""
    return next((r for r in runs if r["method"] == method and r["level"] == level),
                None)


def value(run, key):
    """A run's value of @p key, or None if the run is missing or has none."""
    return None if run is None else run[key]


def text(x, form):
    """@p x formatted with @p form, or '-' if it is None."""
    return "-" if x is None else f"{x:{form}}"


def ratio(a, b):
    """ddfem's mean vertex error over naive's, or None if either is missing."""
    ea, eb = value(a, "mean_vertex_error"), value(b, "mean_vertex_error")
    if ea is None or not eb:
        return None
    return ea / eb


def main(argv):
    if len(argv) > 1 and argv[1] in ("-h", "--help"):
        print(__doc__)
        return
    directory = argv[1] if len(argv) > 1 else os.path.join(
        os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
        "output", "compare")
    # Every scene with a compare run: the shipped ones in the table's order,
    # then any other (a scene of compare_scenes.sh is any prm/<scene>.prm).
    found = sorted(name for name in (os.listdir(directory)
                                     if os.path.isdir(directory) else [])
                   if os.path.isfile(os.path.join(directory, name,
                                                  "comparison.json")))
    scenes = argv[2:] or ([s for s in SCENES if s in found] +
                          [s for s in found if s not in SCENES])
    if not scenes:
        sys.exit(f"Error: no {directory}/<scene>/comparison.json found; run "
                 "scripts/compare_scenes.sh first.")
    for scene in scenes:
        file = os.path.join(directory, scene, "comparison.json")
        if not os.path.exists(file):
            sys.exit(f"Error: no {file}. The scenes are named {', '.join(SCENES)}, "
                     "and each needs a compare run (scripts/compare_scenes.sh).")
    loaded = {scene: load_states(directory, scene) for scene in scenes}

    print("| scene, state | fine / L1 / L2 DoFs | fastest fine run (solver, Newton)"
          " | fine, direct solver | ddfem L1 speedup (vs direct) | L1 mean error ddfem /"
          " naive / average | ddfem / naive | L1 grid bound | ddfem L2 speedup"
          " | L2 mean error ddfem / naive / average | ddfem / naive"
          " | max coarsening (ddfem) | peak memory |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")

    # target -> (states that meet it, states that miss it), in the order
    targets = {name: ([], []) for name in TARGETS}

    def check(name, state, met):
        targets[name][0 if met else 1].append(state)

    for scene in scenes:
        data, states = loaded[scene]
        # The scene the compare run ran, for its targets.
        name_of_run = data.get("scene", scene)
        for index, (state, runs) in enumerate(states.items()):
            label = scene if len(states) == 1 else f"{scene}, {state}"
            fines = [r for r in runs if r["level"] == 0 and r["converged"]]
            fastest = min(fines, key=lambda r: r["wall_time_s"], default=None)
            # 'fine-direct', or 'fine' where the scene's solver is direct.
            direct = next((r for r in runs
                           if r["level"] == 0 and r["linear_solver"] == "direct"),
                          None)
            ddfem = {level: find(runs, "ddfem", level) for level in (1, 2)}
            naive = {level: find(runs, "naive", level) for level in (1, 2)}
            average = {level: find(runs, "average", level) for level in (1, 2)}
            coarse = [r for r in runs if r["level"] > 0]

            dofs = ""
            if index == 0:
                # Every method of a level has the same mesh.
                at_level = [next((r for r in runs if r["level"] == level), None)
                            for level in (0, 1, 2)]
                dofs = " / ".join(str(r["dofs"]) if r else "-" for r in at_level)
            if fastest is None:
                reference = "none converged"
            else:
                reference = (f"{fastest['wall_time_s']:.1f} s ({fastest['method']}, "
                             f"{fastest['linear_solver']}, "
                             f"{fastest['newton_iterations']})")
            if direct is None:
                direct_time = "not run"
            else:
                direct_time = f"{direct['wall_time_s']:.1f} s" + (
                    "" if direct["converged"] else " (not converged)")
            cells = [label, dofs, reference, direct_time]
            for level in (1, 2):
                d, n, a = ddfem[level], naive[level], average[level]
                speedup = text(value(d, "speedup_vs_fine"),
                               ".2f" if level == 1 else ".1f")
                if level == 1 and direct and d is not None:
                    speedup += f" ({text(d['speedup_vs_fine_direct'], '.1f')})"
                errors = " / ".join(text(value(x, "mean_vertex_error"), ".2e")
                                    for x in (d, n, a))
                cells += [speedup, errors, text(ratio(d, n), ".2f")]
                if level == 1:
                    bound = next((x["grid_fit_lower_bound"] for x in coarse
                                  if x["level"] == 1), None)
                    cells.append(text(bound, ".2e"))
            lookups = [r["coarsening_time_s"] for r in runs if r["method"] == "ddfem"]
            cells.append(f"{max(lookups) * 1e3:.2f} ms" if lookups else "-")
            cells.append(f"{data['peak_memory_mb']:.0f} MiB" if index == 0 else "")
            print("| " + " | ".join(cells) + " |")

            # The targets, per state. A model that did not converge misses
            # its speedup target; without a converged fine run there is no
            # speedup to judge, and a missing error is no verdict either.
            for level, goal, form in ((1, 8., ".2f"),
                                      (2, L2_SPEEDUP.get(name_of_run, 15.), ".1f")):
                model = ddfem[level]
                name = L1_SPEED if level == 1 else L2_SPEED
                if model is None or fastest is None:
                    continue
                if not model["converged"]:
                    check(name, f"{label} not converged", False)
                else:
                    speedup = model["speedup_vs_fine"]
                    check(name, f"{label} {speedup:{form}}x", speedup >= goal)
            l1_error = value(ddfem[1], "mean_vertex_error")
            paper = PAPER_L1_ERROR.get(name_of_run)
            if paper is not None and index == 0 and l1_error is not None:
                check(TABLE_1, f"{label} {l1_error:.2e} (paper {paper:.1e})",
                      l1_error <= paper)
            r = ratio(ddfem[1], naive[1])
            if r is not None:
                check(HALF_NAIVE, f"{label} {r:.2f}x", r <= 0.5)
            r = ratio(ddfem[2], naive[2])
            if r is not None:
                check(L2_ERROR, f"{label} {r:.2f}x", r < 1)
            for r in coarse:
                check(COARSENING,
                      f"{label} {r['method']} L{r['level']} "
                      f"{r['coarsening_time_s'] * 1e3:.2f} ms",
                      r["coarsening_time_s"] < 0.05)

    print()
    for name, (met, missed) in targets.items():
        total = len(met) + len(missed)
        if total == 0:
            continue
        if name == COARSENING:
            # One line per coarse model would drown the others: the largest only.
            largest = max(met + missed, key=lambda s: float(s.split()[-2]))
            print(f"- {name}: {len(met)} of {total} models; largest: {largest}")
            continue
        print(f"- {name}: {len(met)} of {total} states")
        if missed:
            print(f"  - missed: {'; '.join(missed)}")
        if met:
            print(f"  - met: {'; '.join(met)}")


if __name__ == "__main__":
    main(sys.argv)
