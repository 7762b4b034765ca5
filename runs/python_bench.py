"""What a run costs in process (the Python package over libvoussoir with cffi) against the
voussoir program, and what threads give a sweep. Prints the table of docs/benchmarks.md
("Python in process"):
  1. the reference run to its collapse: the program (`run --no-record`, which stops there),
     CPU of the process (user + sys), median of REPEAT; in process, voussoir.run(case,
     dynamic__fall_s=0) with its history (every state's time, delta, reactions, energies) and
     without, CPU of this process around the call (time.process_time), median of REPEAT;
  2. the library's own time of the same run (vs_run_wall_s): the program's JSON stats.wall_s
     and Result.wall_s, medians;
  3. a sweep of the reference over 8 directions (0, 10, ..., 70 deg) to the collapse:
     voussoir.sweep with jobs=1 and jobs=2, wall and CPU seconds of this process, median of
     3: the speed-up, and CPU / wall (above 1: threads ran C at once, the GIL released); on a
     machine shared with other work the load average (printed) bounds what threads can give.
usage: /usr/bin/python3 runs/python_bench.py [VOUSSOIR] [REPEAT]  (default build/voussoir, 21)"""
import json
import os
import resource
import statistics
import subprocess
import sys
import time

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "python"))
prog = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "build",
                                                                           "voussoir"))
repeat = int(sys.argv[2]) if len(sys.argv) > 2 else 21
os.environ["VOUSSOIR"] = prog
import voussoir  # noqa: E402

ref = os.path.join(here, "reference.ini")


def child_cpu(args):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(args, capture_output=True, text=True, check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), p.stdout


def own_cpu(fn):
    t0 = time.process_time()
    r = fn()
    return time.process_time() - t0, r


case = voussoir.Case.from_file(ref, dynamic__fall_s=0)
voussoir.run(case)  # load the library, make the callback's types once
prog_cpu, prog_wall, py_cpu, py_cpu_nohist, py_wall = [], [], [], [], []
for _ in range(repeat):  # interleaved, so that a change of load hits both alike
    cpu, out = child_cpu([prog, "run", ref, "--no-record", "--json", "-q"])
    prog_cpu.append(cpu)
    prog_wall.append(json.loads(out)["stats"]["wall_s"])
    cpu, res = own_cpu(lambda: voussoir.run(case))
    py_cpu.append(cpu)
    py_wall.append(res.wall_s)
    py_cpu_nohist.append(own_cpu(lambda: voussoir.run(case, history=False))[0])
med = statistics.median
ms = 1e3
print(f"library {voussoir.library_path()}; {repeat} repeats; load average "
      f"{os.getloadavg()[0]:.2f}")
print("| row | the program | in process | ratio |")
print("|---|---|---|---|")
print(f"| reference to collapse, CPU ms (median of {repeat}) | {med(prog_cpu) * ms:.1f} | "
      f"{med(py_cpu) * ms:.1f} (history), {med(py_cpu_nohist) * ms:.1f} (none) | "
      f"{med(py_cpu) / med(prog_cpu):.2f}, {med(py_cpu_nohist) / med(prog_cpu):.2f} |")
print(f"| the library's own time (vs_run_wall_s), ms | {med(prog_wall) * ms:.1f} | "
      f"{med(py_wall) * ms:.1f} | {med(py_wall) / med(prog_wall):.2f} |")
alphas = list(range(0, 80, 10))
walls, cpus = {}, {}
for jobs in (1, 2):
    w, c = [], []
    for _ in range(3):
        t0, c0 = time.perf_counter(), time.process_time()
        table = voussoir.sweep(ref, alpha=alphas, jobs=jobs)
        w.append(time.perf_counter() - t0)
        c.append(time.process_time() - c0)
    walls[jobs], cpus[jobs] = med(w), med(c)
    assert (table["status"] == "collapse").all(), table
print(f"| sweep, {len(alphas)} directions to collapse, wall s (CPU s), median of 3 | | "
      f"{walls[1]:.3f} ({cpus[1]:.3f}) with jobs=1, {walls[2]:.3f} ({cpus[2]:.3f}) with jobs=2 "
      f"| speed-up {walls[1] / walls[2]:.2f}; CPU / wall with jobs=2 {cpus[2] / walls[2]:.2f} |")
print(f"load average after: {os.getloadavg()[0]:.2f}")
